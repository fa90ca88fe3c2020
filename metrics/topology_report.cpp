// Comparing and printing topology reports (compute_topology is in topology.cpp).
#include <cstdio>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "topotet/metrics/topology.h"

namespace topotet {
using namespace metrics;  // the checker's internals (z2_homology.h, manifold_betti.h, ...)
namespace {

struct NamedComplex {
  std::string name;
  const ComplexTopology* topology;
};

// Every complex of a report with its display name, in a fixed order.
std::vector<NamedComplex> named_complexes(const TopologyReport& r) {
  std::vector<NamedComplex> out;
  out.push_back({"mesh", &r.mesh});
  out.push_back({"boundary", &r.boundary});
  for (const auto& [m, t] : r.materials) out.push_back({"material " + std::to_string(m), &t});
  for (const auto& [ref, t] : r.surfaces) out.push_back({"surface ref " + std::to_string(ref), &t});
  for (const auto& [pair, t] : r.interfaces)
    out.push_back({"interface (" + std::to_string(pair.first) + "," + std::to_string(pair.second) + ")", &t});
  out.push_back({"all surfaces", &r.all_surfaces});
  for (const auto& [ref, t] : r.polylines) out.push_back({"polyline ref " + std::to_string(ref), &t});
  out.push_back({"all polylines", &r.all_polylines});
  out.push_back({"embedded structure", &r.embedded});
  out.push_back({"boundary + embedded", &r.features});
  return out;
}

std::string betti_text(std::int64_t b) { return b == kUnknownBetti ? "?" : std::to_string(b); }

// "b1 1 -> 2, euler 0 -> -1", or empty when nothing known differs.
std::string compare_complex(const ComplexTopology& a, const ComplexTopology& b) {
  std::string out;
  auto add = [&out](const std::string& what, std::int64_t x, std::int64_t y) {
    if (!out.empty()) out += ", ";
    out += what + " " + std::to_string(x) + " -> " + std::to_string(y);
  };
  for (int k = 0; k < 4; ++k) {
    const std::int64_t x = a.betti[k], y = b.betti[k];
    if (x != kUnknownBetti && y != kUnknownBetti && x != y) add(std::string(1, 'b').append(std::to_string(k)), x, y);
  }
  if (a.euler_characteristic != b.euler_characteristic)
    add("euler", a.euler_characteristic, b.euler_characteristic);
  return out;
}

}  // namespace

bool same_topology(const TopologyReport& before, const TopologyReport& after, std::string* differences) {
  std::vector<std::string> lines;
  const std::vector<NamedComplex> a = named_complexes(before), b = named_complexes(after);
  std::map<std::string, const ComplexTopology*> b_by_name;
  for (const auto& c : b) b_by_name[c.name] = c.topology;
  for (const auto& c : a) {
    const auto it = b_by_name.find(c.name);
    if (it == b_by_name.end()) {
      lines.push_back(c.name + ": missing after");
      continue;
    }
    const std::string diff = compare_complex(*c.topology, *it->second);
    if (!diff.empty()) lines.push_back(c.name + ": " + diff);
    b_by_name.erase(it);
  }
  for (const auto& c : b)
    if (b_by_name.count(c.name)) lines.push_back(c.name + ": new after (not in before)");

  if (before.pinned_vertex_count != after.pinned_vertex_count)
    lines.push_back("pinned vertices: " + std::to_string(before.pinned_vertex_count) + " -> " +
                    std::to_string(after.pinned_vertex_count));
  auto must_be_zero = [&lines](const char* what, std::uint64_t count) {
    if (count != 0) lines.push_back(std::string(what) + ": " + std::to_string(count) + " after (must be 0)");
  };
  must_be_zero("inverted tets", after.inverted_tet_count);
  must_be_zero("degenerate tets", after.degenerate_tet_count);
  must_be_zero("faces with more than two tets", after.nonmanifold_face_count);
  must_be_zero("duplicate tets", after.duplicate_tet_count);
  must_be_zero("invalid elements", after.invalid_element_count);
  auto must_not_grow = [&lines](const char* what, std::uint64_t was, std::uint64_t is) {
    if (is > was) lines.push_back(std::string(what) + ": " + std::to_string(was) + " -> " + std::to_string(is));
  };
  must_not_grow("triangles on no tet", before.detached_triangle_count, after.detached_triangle_count);
  must_not_grow("segments on no tet", before.detached_segment_count, after.detached_segment_count);

  if (differences != nullptr) {
    differences->clear();
    for (const auto& line : lines) *differences += line + "\n";
  }
  return lines.empty();
}

std::string format_topology_table(const TopologyReport& report) {
  std::ostringstream out;
  char line[256];
  std::snprintf(line, sizeof line, "%-22s %9s %9s %9s %9s %8s %6s %6s %6s %6s\n", "complex", "V", "E", "F", "T",
                "chi", "b0", "b1", "b2", "b3");
  out << line;
  for (const auto& c : named_complexes(report)) {
    const ComplexTopology& t = *c.topology;
    std::snprintf(line, sizeof line, "%-22s %9lld %9lld %9lld %9lld %8lld %6s %6s %6s %6s\n", c.name.c_str(),
                  static_cast<long long>(t.simplex_count[0]), static_cast<long long>(t.simplex_count[1]),
                  static_cast<long long>(t.simplex_count[2]), static_cast<long long>(t.simplex_count[3]),
                  static_cast<long long>(t.euler_characteristic), betti_text(t.betti[0]).c_str(),
                  betti_text(t.betti[1]).c_str(), betti_text(t.betti[2]).c_str(), betti_text(t.betti[3]).c_str());
    out << line;
  }
  out << "pinned vertices: " << report.pinned_vertex_count << "\n"
      << "inverted tets: " << report.inverted_tet_count << "\n"
      << "degenerate tets: " << report.degenerate_tet_count << "\n"
      << "faces with more than two tets: " << report.nonmanifold_face_count << "\n"
      << "duplicate tets: " << report.duplicate_tet_count << "\n"
      << "invalid elements: " << report.invalid_element_count << "\n"
      << "triangles on no tet: " << report.detached_triangle_count << "\n"
      << "segments on no tet: " << report.detached_segment_count << "\n"
      << "unreferenced vertices: " << report.unreferenced_vertex_count << "\n";
  if (report.is_fast) out << "(fast mode: '?' = not computed)\n";
  return out.str();
}

namespace {

std::string complex_json(const ComplexTopology& t) {
  std::ostringstream out;
  out << "{\"simplices\":[" << t.simplex_count[0] << "," << t.simplex_count[1] << "," << t.simplex_count[2] << ","
      << t.simplex_count[3] << "],\"betti\":[";
  for (int k = 0; k < 4; ++k) {
    if (k > 0) out << ",";
    if (t.betti[k] == kUnknownBetti) {
      out << "null";
    } else {
      out << t.betti[k];
    }
  }
  out << "],\"euler\":" << t.euler_characteristic << "}";
  return out.str();
}

template <class Map, class KeyText>
std::string map_json(const Map& map, KeyText key_text) {
  std::string out = "{";
  for (const auto& [key, t] : map) {
    if (out.size() > 1) out += ",";
    out.append(1, '"').append(key_text(key)).append("\":").append(complex_json(t));
  }
  return out + "}";
}

}  // namespace

std::string topology_to_json(const TopologyReport& r) {
  auto int_key = [](std::int32_t k) { return std::to_string(k); };
  auto pair_key = [](const MaterialPair& p) { return std::to_string(p.first) + "," + std::to_string(p.second); };
  std::ostringstream out;
  out << "{\"fast\":" << (r.is_fast ? "true" : "false") << ",\"mesh\":" << complex_json(r.mesh)
      << ",\"boundary\":" << complex_json(r.boundary) << ",\"materials\":" << map_json(r.materials, int_key)
      << ",\"surfaces\":" << map_json(r.surfaces, int_key) << ",\"interfaces\":" << map_json(r.interfaces, pair_key)
      << ",\"all_surfaces\":" << complex_json(r.all_surfaces) << ",\"polylines\":" << map_json(r.polylines, int_key)
      << ",\"all_polylines\":" << complex_json(r.all_polylines) << ",\"embedded\":" << complex_json(r.embedded)
      << ",\"features\":" << complex_json(r.features)
      << ",\"pinned_vertices\":" << r.pinned_vertex_count << ",\"inverted_tets\":" << r.inverted_tet_count
      << ",\"degenerate_tets\":" << r.degenerate_tet_count << ",\"nonmanifold_faces\":" << r.nonmanifold_face_count
      << ",\"duplicate_tets\":" << r.duplicate_tet_count << ",\"invalid_elements\":" << r.invalid_element_count
      << ",\"detached_triangles\":" << r.detached_triangle_count
      << ",\"detached_segments\":" << r.detached_segment_count
      << ",\"unreferenced_vertices\":" << r.unreferenced_vertex_count << "}";
  return out.str();
}

}  // namespace topotet
