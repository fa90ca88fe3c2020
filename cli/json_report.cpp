#include "json_report.h"

#include <numbers>

#include "topotet/version.h"

namespace topotet::cli {
namespace {

constexpr double kRadiansPerDegree = std::numbers::pi / 180.0;

Json sample_json(const SampleStats& s) {
  return {{"count", s.count}, {"min", s.min}, {"max", s.max}, {"mean", s.mean}, {"std_dev", s.std_dev}};
}

}  // namespace

Json json_header(const std::string& command) {
  Json j;
  j["schema_version"] = kJsonSchemaVersion;
  j["topotet_version"] = TOPOTET_VERSION_STRING;
  j["command"] = command;
  return j;
}

Json mesh_json(const std::string& file, const MeshData& mesh, double read_seconds) {
  return {{"file", file}, {"vertices", mesh.vertex_count()}, {"tets", mesh.tet_count()}, {"read_seconds", read_seconds}};
}

Json quality_json(const QualityStats& q) {
  return {{"tets", q.tet_count},
          {"dihedral_deg", sample_json(q.dihedral_deg)},
          {"solid_sr", sample_json(q.solid_sr)},
          {"face_deg", sample_json(q.face_deg)},
          {"mean_ratio", sample_json(q.mean_ratio)},
          {"std_dev_dihedral_rad", q.dihedral_deg.std_dev * kRadiansPerDegree},
          {"std_dev_solid_sr", q.solid_sr.std_dev},
          {"std_dev_face_rad", q.face_deg.std_dev * kRadiansPerDegree},
          {"min_mean_ratio", q.mean_ratio.min},
          {"inverted_tets", q.inverted},
          {"zero_volume_tets", q.zero_volume},
          {"tets_under_10_deg", q.under_10_deg},
          {"tets_under_5_deg", q.under_5_deg}};
}

Json topology_report_json(const topotet::TopologyReport& r) { return Json::parse(topotet::topology_to_json(r)); }

std::vector<std::string> split_lines(const std::string& text) {
  std::vector<std::string> lines;
  std::size_t begin = 0;
  while (begin < text.size()) {
    std::size_t end = text.find('\n', begin);
    if (end == std::string::npos) end = text.size();
    if (end > begin) lines.push_back(text.substr(begin, end - begin));
    begin = end + 1;
  }
  return lines;
}

}  // namespace topotet::cli
