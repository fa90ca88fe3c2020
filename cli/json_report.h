// The JSON reports of `simplify`, `info` and `check` (--json FILE), schema version 2.
//
// Every report starts with the same three keys, and describes a mesh with the same keys wherever
// one appears (simplify's "input", info's "input", check's "before" and "after"), so a script that
// reads one command's report reads the others:
//   schema_version   bumped when a key changes meaning or goes away (new keys keep it)
//   topotet_version  the version that wrote it
//   command          "simplify", "info" or "check"
//   mesh: file, vertices, tets, read_seconds, then as the command measures them: build_seconds,
//         model_bytes, model_bytes_per_tet, quality{...} + quality_seconds,
//         topology_report{...} + topology_seconds
//   verdict: topology ("pass", "fail" or "skipped") and topology_differences [lines]
// Times are seconds and end in _seconds; counts are plain integers; names are snake_case. docs/cli.md
// ("JSON reports") lists every key.
#pragma once

#include <string>
#include <vector>

#include "common.h"
#include "topotet/metrics/quality.h"
#include "topotet/metrics/topology.h"

namespace topotet::cli {

inline constexpr int kJsonSchemaVersion = 2;

// {schema_version, topotet_version, command}: the first keys of every report.
Json json_header(const std::string& command);

// {file, vertices, tets, read_seconds}: the start of every mesh object.
Json mesh_json(const std::string& file, const MeshData& mesh, double read_seconds);

// Angle and mean-ratio statistics (metrics/quality.h), angles' standard deviations in rad and sr.
Json quality_json(const QualityStats& q);

// The checker's report (Betti numbers and Euler characteristic of every complex).
Json topology_report_json(const topotet::TopologyReport& r);

// The non-empty lines of `text` (the checker's differences), as a JSON array.
std::vector<std::string> split_lines(const std::string& text);

}  // namespace topotet::cli
