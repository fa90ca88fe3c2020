// topotet info FILE [--json F]: what a mesh file holds, and whether it builds into a valid model.
#include <algorithm>
#include <cstdio>
#include <limits>
#include <map>
#include <memory>
#include <set>

#include <glm/common.hpp>

#include "common.h"
#include "json_report.h"
#include "topotet/error.h"
#include "topotet/features.h"
#include "topotet/simplify.h"
#include "topotet/metrics/topology.h"

namespace topotet::cli {
namespace {

struct InfoArgs {
  std::string input;
  std::string json_path;
  bool tets_only = false;
  std::string material_array;
  std::string format;
  double feature_angle = SimplifyOptions{}.feature_angle;
};

template <class Element>
std::map<std::int32_t, std::uint64_t> count_by_ref(const std::vector<Element>& elements) {
  std::map<std::int32_t, std::uint64_t> out;
  for (const Element& e : elements) ++out[e.ref];
  return out;
}

// "3 (ref 1: 2, ref 10: 1)"
std::string by_ref_text(std::uint64_t total, const std::map<std::int32_t, std::uint64_t>& counts, const char* what) {
  std::string s = format_count(total);
  if (counts.empty()) return s;
  s += " (";
  bool first = true;
  for (const auto& [ref, n] : counts) {
    if (!first) s += ", ";
    first = false;
    s += std::string(what) + " " + std::to_string(ref) + ": " + format_count(n);
  }
  return s + ")";
}

Json counts_json(const std::map<std::int32_t, std::uint64_t>& counts) {
  Json j = Json::object();
  for (const auto& [ref, n] : counts) j[std::to_string(ref)] = n;
  return j;
}

int run_info(const InfoArgs& args) {
  check_output_folder(args.json_path);
  double read_seconds = 0.0;
  ReadOptions read_options;
  read_options.tets_only = args.tets_only;
  read_options.material_array = args.material_array;
  read_options.format = format_for(args.input, args.format);
  if (args.json_path == "-") send_report_to_stderr();
  const MeshData data = read_input(args.input, &read_seconds, read_options);

  const auto materials = [&] {
    std::map<std::int32_t, std::uint64_t> out;
    if (data.tet_material.empty()) {
      if (!data.tets.empty()) out[0] = data.tets.size();
    } else {
      for (std::int32_t m : data.tet_material) ++out[m];
    }
    return out;
  }();
  const auto triangles = count_by_ref(data.triangles);
  const auto segments = count_by_ref(data.segments);
  std::set<VertId> pinned(data.corners.begin(), data.corners.end());
  pinned.insert(data.required_vertices.begin(), data.required_vertices.end());

  std::array<double, 3> lo, hi;
  lo.fill(std::numeric_limits<double>::infinity());
  hi.fill(-std::numeric_limits<double>::infinity());
  for (const std::array<double, 3>& p : data.positions)
    for (int k = 0; k < 3; ++k) {
      lo[k] = std::min(lo[k], p[k]);
      hi[k] = std::max(hi[k], p[k]);
    }

  // Topology first (it never throws on bad input), then validation by building the model.
  const Stopwatch topology_clock;
  topotet::TopologyOptions topology_options;
  // -v: every complex's Betti numbers, as `check` computes them; else the fast mode's Euler
  // characteristics and components, which every mesh size affords.
  topology_options.fast = verbosity() < Verbosity::kVerbose;
  const topotet::TopologyReport topology = topotet::compute_topology(data, topology_options);
  const double topology_seconds = topology_clock.seconds();

  std::string build_error;
  double build_seconds = 0.0;
  std::size_t model_bytes = 0;
  FeatureStats features;
  double feature_seconds = 0.0;
  try {
    TetMesh mesh = build_input(args.input, data, &build_seconds);
    model_bytes = mesh.memory_bytes();
    const Stopwatch feature_clock;
    features = detect_features(mesh, args.feature_angle, feature_scale(mesh, SimplifyOptions{}));
    feature_seconds = feature_clock.seconds();
  } catch (const InputError& e) {
    build_error = e.what();
  }

  const auto row = [](const char* key, const std::string& value) { std::fprintf(report_stream(), "%-14s %s\n", key, value.c_str()); };
  row("file", args.input + " (read " + format_seconds(read_seconds) + ")");
  row("vertices", format_count(data.vertex_count()));
  row("tets", format_count(data.tet_count()));
  std::string material_text = std::to_string(materials.size());
  if (!materials.empty()) {
    material_text += " (";
    bool first = true;
    for (const auto& [m, n] : materials) {
      material_text += (first ? "" : ", ") + std::to_string(m) + ": " + format_count(n) + " tets";
      first = false;
    }
    material_text += ")";
  }
  row("materials", material_text);
  row("triangles", by_ref_text(data.triangles.size(), triangles, "ref"));
  row("edges", by_ref_text(data.segments.size(), segments, "ref") +
                   (data.ridges.empty() ? "" : ", " + format_count(data.ridges.size()) + " ridges"));
  row("pinned", format_count(pinned.size()) + " vertices (" + format_count(data.corners.size()) + " corners, " +
                    format_count(data.required_vertices.size()) + " required)");
  std::string field_text = std::to_string(data.fields.size());
  if (!data.fields.empty()) {
    field_text += " (";
    for (std::size_t i = 0; i < data.fields.size(); ++i)
      field_text += (i ? ", " : "") + data.fields[i].name + ": " + std::to_string(data.fields[i].components) +
                    (data.fields[i].components == 1 ? " component" : " components");
    field_text += ")";
  }
  row("fields", field_text);
  std::string cell_text = std::to_string(data.cell_fields.size());
  if (!data.cell_fields.empty()) {
    cell_text += " (";
    for (std::size_t i = 0; i < data.cell_fields.size(); ++i) {
      const CellField& f = data.cell_fields[i];
      cell_text += (i ? ", " : "") + f.name + ": " + cell_kind_name(f.kind) +
                   (f.components == 1 ? "" : ", " + std::to_string(f.components) + " components");
    }
    cell_text += ")";
  }
  row("cell arrays", cell_text);
  if (!data.positions.empty())
    row("bounding box", "[" + format_number(lo[0], 6) + ", " + format_number(hi[0], 6) + "] x [" +
                            format_number(lo[1], 6) + ", " + format_number(hi[1], 6) + "] x [" +
                            format_number(lo[2], 6) + ", " + format_number(hi[2], 6) + "]");
  row("euler", "mesh " + std::to_string(topology.mesh.euler_characteristic) + ", boundary " +
                   std::to_string(topology.boundary.euler_characteristic) + "; " +
                   std::to_string(topology.mesh.betti[0]) + " connected component" +
                   (topology.mesh.betti[0] == 1 ? "" : "s") + " (" + format_seconds(topology_seconds) + ")");
  if (!topology_options.fast)
    for (const std::string& line : split_lines(topotet::format_topology_table(topology)))
      std::fprintf(report_stream(), "%-14s %s\n", "", line.c_str());
  if (build_error.empty()) {
    row("model", format_count(data.tet_count() ? model_bytes / data.tet_count() : 0) + " bytes/tet, " +
                     format_bytes(model_bytes) + " (build " + format_seconds(build_seconds) + ")");
    if (args.feature_angle < 180.0)
      row("features", format_count(features.edges) + " sharp edges (> " + format_number(args.feature_angle) +
                          " degrees and higher than the default tolerance; " + format_count(features.candidates) +
                          " by the angle alone), " + format_count(features.corners) + " corners (" +
                          format_seconds(feature_seconds) + ")");
    row("valid", "yes");
  } else {
    row("valid", "no (see the error)");
  }

  if (!args.json_path.empty()) {
    Json j = json_header("info");
    Json in = mesh_json(args.input, data, read_seconds);
    in["valid"] = build_error.empty();
    if (build_error.empty()) {
      in["build_seconds"] = build_seconds;
      in["model_bytes"] = model_bytes;
      in["model_bytes_per_tet"] = data.tet_count() ? static_cast<double>(model_bytes) / data.tet_count() : 0.0;
    } else {
      in["error"] = build_error;
    }
    in["materials"] = counts_json(materials);
    in["triangles"] = data.triangles.size();
    in["triangles_by_ref"] = counts_json(triangles);
    in["edges"] = data.segments.size();
    in["edges_by_ref"] = counts_json(segments);
    in["ridges"] = data.ridges.size();
    in["corners"] = data.corners.size();
    in["required_vertices"] = data.required_vertices.size();
    in["pinned_vertices"] = pinned.size();
    in["fields"] = Json::array();
    for (const VertexField& f : data.fields) in["fields"].push_back({{"name", f.name}, {"components", f.components}});
    in["cell_arrays"] = Json::array();
    for (const CellField& f : data.cell_fields)
      in["cell_arrays"].push_back({{"name", f.name}, {"components", f.components}, {"kind", cell_kind_name(f.kind)}});
    if (!data.positions.empty()) {
      in["bounding_box"] = {{"min", lo}, {"max", hi}};
    } else {
      in["bounding_box"] = nullptr;
    }
    // The fast checker's numbers (Euler characteristics and components), as `check --fast` gives them.
    in["euler_characteristic"] = topology.mesh.euler_characteristic;
    in["boundary_euler_characteristic"] = topology.boundary.euler_characteristic;
    in["connected_components"] = topology.mesh.betti[0];
    if (!topology_options.fast) in["topology_report"] = topology_report_json(topology);
    in["topology_seconds"] = topology_seconds;
    if (build_error.empty()) {
      in["feature_angle"] = args.feature_angle;
      in["feature_edges"] = features.edges;
      in["feature_corners"] = features.corners;
      in["feature_candidates"] = features.candidates;
      in["feature_turns"] = features.turns;
      in["feature_seconds"] = feature_seconds;
    }
    j["input"] = in;
    write_json_atomically(args.json_path, j);
  }
  if (!build_error.empty()) throw InputError(build_error);
  return kExitOk;
}

}  // namespace

void add_info_command(CLI::App& app, CommandRunner& run) {
  auto args = std::make_shared<InfoArgs>();
  CLI::App* cmd = app.add_subcommand("info", "Counts, substructures, fields, bounding box, Euler characteristic, "
                                             "memory per tet; validates by building the model (exit 2 if invalid).");
  cmd->add_option("FILE", args->input, "Mesh file (.mesh, .meshb, .msh, optionally .gz)")->required();
  cmd->add_option("--json", args->json_path, "Also write the numbers as JSON to this file");
  cmd->add_option("--format", args->format, "Format of FILE when it is - (stdin): mesh or msh");
  add_verbosity_flags(cmd);
  cmd->add_flag("--tets-only", args->tets_only, "Leave hexahedra, prisms and pyramids out of a mixed mesh (with a warning and their count) instead of refusing it");
  cmd->add_option("--material-array", args->material_array, kMaterialArrayHelp);
  cmd->add_option("--feature-angle", args->feature_angle,
                  "Count the sharp edges (faces turning by more than this many degrees) and corners simplify keeps; "
                  "180 = off")
      ->check(CLI::Range(0.0, 180.0))
      ->capture_default_str();
  cmd->callback([args, &run] { run = [args] { return run_info(*args); }; });
}

}  // namespace topotet::cli
