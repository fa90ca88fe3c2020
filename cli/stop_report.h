// Why a run stopped before its target and what to change (Report::stop, issue #23), for the text
// report and the JSON report of `topotet simplify`.
#pragma once

#include "common.h"
#include "topotet/simplify.h"

namespace topotet::cli {

// The "stopped" and "pinned" rows and the suggestion ("next step"); nothing when the run reached
// its target.
void print_stop_report(const Report& report);

// {"vertices", "refused_by": {reason: share}, "pinned_vertices": {...}, "dominant", "suggestion"},
// or null when the run reached its target.
Json stop_report_json(const Report& report);

}  // namespace topotet::cli
