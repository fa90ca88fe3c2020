// Text and JSON forms of SurfaceDistance (see distance_report.h).
#include "distance_report.h"

#include <cmath>
#include <cstdio>

namespace topotet::cli {
namespace {

std::string length_text(double x, double diagonal) {
  if (!std::isfinite(x)) return "inf";
  return format_number(x) + (diagonal > 0 ? " (" + format_number(x / diagonal) + " diag)" : "");
}

Json number_or_null(double x) { return std::isfinite(x) ? Json(x) : Json(nullptr); }

}  // namespace

void print_surface_distance(const SurfaceDistance& d, double seconds, bool per_label) {
  const LabelDistance* worst = nullptr;
  for (const LabelDistance& l : d.labels)
    if (worst == nullptr || l.hausdorff > worst->hausdorff) worst = &l;
  std::fprintf(report_stream(), "%-10sHausdorff %s: in->out %s, out->in %s%s; sampling error <= %s (%s samples, %s)\n", "distance",
              length_text(d.hausdorff, d.diagonal).c_str(), format_number(d.original_to_simplified).c_str(),
              format_number(d.simplified_to_original).c_str(),
              worst != nullptr ? (", worst " + worst->name()).c_str() : "", format_number(d.sampling_error).c_str(),
              format_count(d.samples).c_str(), format_seconds(seconds).c_str());
  if (!per_label) return;
  for (const LabelDistance& l : d.labels)
    std::fprintf(report_stream(), "%-10s  %-36s %s (in->out %s, out->in %s)\n", "", l.name().c_str(),
                length_text(l.hausdorff, d.diagonal).c_str(), format_number(l.original_to_simplified).c_str(),
                format_number(l.simplified_to_original).c_str());
}

Json surface_distance_json(const SurfaceDistance& d) {
  Json labels = Json::array();
  for (const LabelDistance& l : d.labels) {
    Json j{{"name", l.name()}, {"polyline", l.polyline}, {"ref", l.ref}};
    if (!l.polyline) {
      j["material_low"] = l.material_low;
      j["material_high"] = l.material_high;
    }
    j["hausdorff"] = number_or_null(l.hausdorff);
    j["original_to_simplified"] = number_or_null(l.original_to_simplified);
    j["simplified_to_original"] = number_or_null(l.simplified_to_original);
    j["original_primitives"] = l.original_primitives;
    j["simplified_primitives"] = l.simplified_primitives;
    j["original_samples"] = l.original_samples;
    j["simplified_samples"] = l.simplified_samples;
    labels.push_back(j);
  }
  return {{"hausdorff", number_or_null(d.hausdorff)},
          {"hausdorff_rel", number_or_null(d.diagonal > 0 ? d.hausdorff / d.diagonal : d.hausdorff)},
          {"original_to_simplified", number_or_null(d.original_to_simplified)},
          {"simplified_to_original", number_or_null(d.simplified_to_original)},
          {"diagonal", d.diagonal},
          {"sample_spacing", d.sample_spacing},
          {"sampling_error", d.sampling_error},
          {"samples", d.samples},
          {"unmatched_labels", d.unmatched_labels},
          {"labels", labels}};
}

}  // namespace topotet::cli
