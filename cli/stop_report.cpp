// print_stop_report, stop_report_json (stop_report.h).
#include "stop_report.h"

#include <cstdio>
#include <string>
#include <utility>
#include <vector>

namespace topotet::cli {
namespace {

std::vector<std::pair<const char*, std::uint64_t>> reasons(const StopDiagnosis& d) {
  return {{"topology", d.topology}, {"pinned", d.pinned},         {"inversion", d.inversion},
          {"quality", d.quality},   {"tolerance", d.tolerance},   {"field_error", d.field_error},
          {"collapsible", d.collapsible}};
}

double share(std::uint64_t n, std::uint64_t of) { return of ? static_cast<double>(n) / static_cast<double>(of) : 0.0; }

std::string percent(double s) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.0f%%", 100.0 * s);
  return buf;
}

}  // namespace

void print_stop_report(const Report& report) {
  const StopDiagnosis& d = report.stop;
  if (!d.is_filled) return;
  const auto row = [](const char* key, const std::string& value) {
    std::fprintf(report_stream(), "%-10s%s\n", key, value.c_str());
  };
  std::string refused = format_count(d.vertices) + " vertices left, held by";
  bool first = true;
  for (const auto& [name, n] : reasons(d)) {
    if (n == 0) continue;
    refused += std::string(first ? " " : ", ") + name + " " + percent(share(n, d.vertices));
    first = false;
  }
  row("stopped", refused);
  row("pinned", format_count(d.pinned_corners + d.pinned_required + d.pinned_features + d.pinned_other) +
                    " vertices: " + format_count(d.pinned_corners) + " listed corners, " +
                    format_count(d.pinned_required) + " required, " + format_count(d.pinned_features) +
                    " feature corners" + (d.pinned_other ? ", " + format_count(d.pinned_other) + " other" : ""));
  if (!d.suggestion.empty()) row("next step", d.suggestion);
}

Json stop_report_json(const Report& report) {
  const StopDiagnosis& d = report.stop;
  if (!d.is_filled) return Json(nullptr);
  Json refused = Json::object(), counts = Json::object();
  for (const auto& [name, n] : reasons(d)) {
    refused[name] = share(n, d.vertices);
    counts[name] = n;
  }
  Json j;
  j["vertices"] = d.vertices;
  j["refused_by"] = refused;
  j["refused_count"] = counts;
  j["pinned_vertices"] = {{"listed_corners", d.pinned_corners},
                          {"required", d.pinned_required},
                          {"feature_corners", d.pinned_features},
                          {"other", d.pinned_other}};
  j["dominant"] = d.dominant;
  j["dominant_share"] = d.dominant_share;
  j["beyond_reach"] = d.beyond_reach;
  j["suggestion"] = d.suggestion;
  return j;
}

}  // namespace topotet::cli
