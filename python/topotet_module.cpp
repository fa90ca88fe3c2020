// The extension `topotet._core` of the Python package `topotet` (python/topotet/: the package
// re-exports all of it, and adds the meshio and VTK adapters and `python -m topotet`): numpy arrays
// in and out.
//
//   out = topotet.simplify(points, tets, materials=None, fields=None, ratio=0.25, tolerance_rel=0.004,
//                          feature_angle=45, threads=0, ...)   (every default is SimplifyOptions')
//   out["points"], out["tets"], out["materials"], out["fields"], out["cell_fields"], out["vertex_map"],
//   out["report"]
//   mesh = topotet.read("in.mesh");  topotet.write("out.msh", mesh)
//
// A mesh is a dict of arrays: points (n, 3) float64, tets (m, 4) int64 (0-based), materials (m,)
// int32, triangles (k, 3) / triangle_refs (k,), segments (s, 2) / segment_refs (s,), corners (c,),
// fields {name: (n,) or (n, components) float64}, cell_fields {name: (m,) or (m, components) float64}
// with cell_kinds {name: "intensive" | "categorical" | "extensive"} (topotet/cell_fields.h: how each
// is carried onto the simplified tets). Inputs may be any numeric dtype and any strides;
// simplify() builds the model straight from points, tets, materials and fields when they are
// float64/float32 and int32/int64 (engine/mesh/mesh_view.h: no copy besides the model), and converts
// other dtypes once. Bad input raises ValueError with the library's one-line message; the GIL is
// released while the library works.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "mesh/mesh_view.h"
#include "topotet/cell_fields.h"
#include "topotet/error.h"
#include "topotet/hierarchy.h"
#include "topotet/io.h"
#include "topotet/isosurface.h"
#include "topotet/out_of_core.h"
#include "topotet/simplify.h"
#include "topotet/threads.h"
#include "topotet/version.h"
#include "topotet/vertex_map_file.h"

namespace py = pybind11;

namespace {

using topotet::VertId;
using Reals = py::array_t<double, py::array::forcecast>;
using Ints = py::array_t<std::int64_t, py::array::forcecast>;

void require_shape(const py::array& a, py::ssize_t width, const char* what) {
  if (a.ndim() != 2 || a.shape(1) != width)
    throw py::value_error(std::string(what) + " must have shape (n, " + std::to_string(width) + ")");
}

template <std::size_t N>
std::vector<std::array<VertId, N>> cells(const py::object& obj, const char* what) {
  std::vector<std::array<VertId, N>> out;
  if (obj.is_none()) return out;
  const Ints a = obj.cast<Ints>();
  require_shape(a, N, what);
  const auto r = a.unchecked<2>();
  out.resize(static_cast<std::size_t>(r.shape(0)));
  for (py::ssize_t i = 0; i < r.shape(0); ++i)
    for (py::ssize_t c = 0; c < static_cast<py::ssize_t>(N); ++c) {
      const std::int64_t x = r(i, c);
      if (x < 0 || x >= static_cast<std::int64_t>(topotet::kInvalid))
        throw py::value_error(std::string(what) + " " + std::to_string(i) + ": vertex index " + std::to_string(x) +
                              " out of range (indices are 0-based)");
      out[i][c] = static_cast<VertId>(x);
    }
  return out;
}

std::vector<std::int32_t> labels(const py::object& obj, std::size_t count, const char* what) {
  std::vector<std::int32_t> out;
  if (obj.is_none()) return out;
  const Ints a = obj.cast<Ints>();
  if (a.ndim() != 1 || static_cast<std::size_t>(a.shape(0)) != count)
    throw py::value_error(std::string(what) + " must have shape (" + std::to_string(count) + ",)");
  const auto r = a.unchecked<1>();
  out.resize(count);
  for (py::ssize_t i = 0; i < r.shape(0); ++i) {
    if (r(i) < INT32_MIN || r(i) > INT32_MAX) throw py::value_error(std::string(what) + ": value out of int32 range");
    out[i] = static_cast<std::int32_t>(r(i));
  }
  return out;
}

// The listed triangles, segments and corners (small next to the volume: copied), into a
// MeshData or a MeshView alike.
template <class Mesh>
void add_substructures(Mesh& d, const py::object& triangles, const py::object& triangle_refs,
                       const py::object& segments, const py::object& segment_refs, const py::object& corners) {
  const auto tri = cells<3>(triangles, "triangle");
  const auto tri_refs = labels(triangle_refs, tri.size(), "triangle_refs");
  for (std::size_t i = 0; i < tri.size(); ++i) d.triangles.push_back({tri[i], tri_refs.empty() ? 0 : tri_refs[i]});
  const auto seg = cells<2>(segments, "segment");
  const auto seg_refs = labels(segment_refs, seg.size(), "segment_refs");
  for (std::size_t i = 0; i < seg.size(); ++i) d.segments.push_back({seg[i], seg_refs.empty() ? 0 : seg_refs[i]});
  if (!corners.is_none()) {
    Ints c = corners.cast<Ints>();
    for (const auto& x : cells<1>(c.reshape({c.size(), py::ssize_t{1}}), "corner")) d.corners.push_back(x[0]);
  }
}

topotet::CellFieldKind cell_kind(const std::string& name, const std::string& kind) {
  for (const auto k : {topotet::CellFieldKind::kIntensive, topotet::CellFieldKind::kCategorical, topotet::CellFieldKind::kExtensive})
    if (kind == topotet::cell_kind_name(k)) return k;
  throw py::value_error("cell field " + name + ": kind must be 'intensive', 'categorical' or 'extensive', got '" + kind + "'");
}

// cell_fields {name: (m,) or (m, components)} for m tets, with their kinds {name: kind} (default
// intensive; a kind for an array that is not there is an error).
std::vector<topotet::CellField> to_cell_fields(const py::object& cell_fields, const py::object& cell_kinds, std::size_t tets) {
  std::vector<topotet::CellField> out;
  if (!cell_fields.is_none()) {
    for (const auto& [key, value] : cell_fields.cast<py::dict>()) {
      const std::string name = py::str(key);
      Reals a = value.cast<Reals>();
      if (a.ndim() == 1) a = a.reshape({a.shape(0), py::ssize_t{1}}).cast<Reals>();
      if (a.ndim() != 2 || static_cast<std::size_t>(a.shape(0)) != tets)
        throw py::value_error("cell field " + name + " must have shape (m,) or (m, components) with m = number of tets (" +
                              std::to_string(tets) + ")");
      const auto r = a.unchecked<2>();
      topotet::CellField f{name, static_cast<int>(r.shape(1)), topotet::CellFieldKind::kIntensive, {}};
      f.values.reserve(static_cast<std::size_t>(r.shape(0) * r.shape(1)));
      for (py::ssize_t t = 0; t < r.shape(0); ++t)
        for (py::ssize_t c = 0; c < r.shape(1); ++c) f.values.push_back(r(t, c));
      out.push_back(std::move(f));
    }
  }
  if (!cell_kinds.is_none()) {
    for (const auto& [key, value] : cell_kinds.cast<py::dict>()) {
      const std::string name = py::str(key);
      const auto it = std::find_if(out.begin(), out.end(), [&](const topotet::CellField& f) { return f.name == name; });
      if (it == out.end()) throw py::value_error("cell_kinds names " + name + ", which is not a cell field");
      it->kind = cell_kind(name, py::str(value));
    }
  }
  return out;
}

topotet::MeshData to_mesh_data(const py::object& points, const py::object& tets, const py::object& materials,
                               const py::object& triangles, const py::object& triangle_refs,
                               const py::object& segments, const py::object& segment_refs, const py::object& corners,
                               const py::object& fields, const py::object& cell_fields, const py::object& cell_kinds) {
  topotet::MeshData d;
  const Reals p = points.cast<Reals>();
  require_shape(p, 3, "points");
  const auto rp = p.unchecked<2>();
  d.positions.resize(static_cast<std::size_t>(rp.shape(0)));
  for (py::ssize_t v = 0; v < rp.shape(0); ++v) d.positions[v] = {rp(v, 0), rp(v, 1), rp(v, 2)};
  d.tets = cells<4>(tets, "tet");
  d.tet_material = labels(materials, d.tets.size(), "materials");
  if (d.tet_material.empty()) d.tet_material.assign(d.tets.size(), 0);
  add_substructures(d, triangles, triangle_refs, segments, segment_refs, corners);
  if (!fields.is_none()) {
    for (const auto& [key, value] : fields.cast<py::dict>()) {
      const std::string name = py::str(key);
      Reals a = value.cast<Reals>();
      if (a.ndim() == 1) a = a.reshape({a.shape(0), py::ssize_t{1}}).cast<Reals>();
      if (a.ndim() != 2 || static_cast<std::size_t>(a.shape(0)) != d.positions.size())
        throw py::value_error("field " + name + " must have shape (n,) or (n, components) with n = number of points");
      const auto r = a.unchecked<2>();
      topotet::VertexField f{name, static_cast<int>(r.shape(1)), {}};
      f.values.reserve(static_cast<std::size_t>(r.shape(0) * r.shape(1)));
      for (py::ssize_t v = 0; v < r.shape(0); ++v)
        for (py::ssize_t c = 0; c < r.shape(1); ++c) f.values.push_back(r(v, c));
      d.fields.push_back(std::move(f));
    }
  }
  d.cell_fields = to_cell_fields(cell_fields, cell_kinds, d.tets.size());
  return d;
}

// Whether `a` holds T in native byte order. Not dtype identity: numpy makes equal dtypes that are
// distinct objects (meshio's arrays read from a .vtu have one), which were taken for int64 here.
template <class T>
bool holds(const py::array& a) {
  return py::isinstance<py::array_t<T>>(a);
}

// A numpy array that the builder reads in place when its dtype is one it reads (float64 or
// float32, int32 or int64, native byte order), with any strides; another dtype is converted once.
py::array readable(const py::object& obj, bool integer) {
  py::array a = py::array::ensure(obj);
  if (!a) throw py::value_error("expected an array");
  const bool in_place = integer ? holds<std::int32_t>(a) || holds<std::int64_t>(a) : holds<double>(a) || holds<float>(a);
  if (in_place) return a;
  return integer ? py::array(obj.cast<Ints>()) : py::array(obj.cast<Reals>());
}

topotet::StridedArray strided(const py::array& a) {
  using Type = topotet::StridedArray::Type;
  const Type type = holds<double>(a)         ? Type::kFloat64
                    : holds<float>(a)        ? Type::kFloat32
                    : holds<std::int32_t>(a) ? Type::kInt32
                                             : Type::kInt64;
  return {a.data(), type, a.ndim() > 0 ? a.strides(0) : 0, a.ndim() > 1 ? a.strides(1) : 0};
}

// simplify()'s input: the points, tets, materials and fields are read in place by the builder,
// straight into the model (no MeshData in between); `keep` holds the arrays read.
topotet::MeshView to_mesh_view(const py::object& points, const py::object& tets, const py::object& materials,
                               const py::object& triangles, const py::object& triangle_refs,
                               const py::object& segments, const py::object& segment_refs, const py::object& corners,
                               const py::object& fields, std::vector<py::array>& keep) {
  topotet::MeshView d;
  const py::array& p = keep.emplace_back(readable(points, false));
  require_shape(p, 3, "points");
  d.vertex_count = static_cast<std::size_t>(p.shape(0));
  d.positions = strided(p);
  const py::array& t = keep.emplace_back(readable(tets, true));
  require_shape(t, 4, "tets");
  d.tet_count = static_cast<std::size_t>(t.shape(0));
  d.tets = strided(t);
  if (!materials.is_none()) {
    const py::array& m = keep.emplace_back(readable(materials, true));
    if (m.ndim() != 1 || static_cast<std::size_t>(m.shape(0)) != d.tet_count)
      throw py::value_error("materials must have shape (" + std::to_string(d.tet_count) + ",)");
    d.materials = strided(m);
  }
  add_substructures(d, triangles, triangle_refs, segments, segment_refs, corners);
  if (!fields.is_none()) {
    for (const auto& [key, value] : fields.cast<py::dict>()) {
      const std::string name = py::str(key);
      py::array a = readable(py::reinterpret_borrow<py::object>(value), false);
      if (a.ndim() == 1) a = a.reshape({a.shape(0), py::ssize_t{1}});
      if (a.ndim() != 2 || static_cast<std::size_t>(a.shape(0)) != d.vertex_count)
        throw py::value_error("field " + name + " must have shape (n,) or (n, components) with n = number of points");
      d.fields.push_back({name, static_cast<int>(a.shape(1)), strided(keep.emplace_back(std::move(a)))});
    }
  }
  return d;
}

template <class T, std::size_t N>
py::array_t<T> rows(const std::vector<std::array<VertId, N>>& cells) {
  py::array_t<T> out({static_cast<py::ssize_t>(cells.size()), static_cast<py::ssize_t>(N)});
  auto w = out.template mutable_unchecked<2>();
  for (std::size_t i = 0; i < cells.size(); ++i)
    for (std::size_t c = 0; c < N; ++c) w(i, c) = static_cast<T>(cells[i][c]);
  return out;
}

py::dict to_dict(const topotet::MeshData& d) {
  py::dict out;
  py::array_t<double> points({static_cast<py::ssize_t>(d.positions.size()), py::ssize_t{3}});
  auto wp = points.mutable_unchecked<2>();
  for (std::size_t v = 0; v < d.positions.size(); ++v)
    for (int c = 0; c < 3; ++c) wp(v, c) = d.positions[v][c];
  out["points"] = points;
  out["tets"] = rows<std::int64_t>(d.tets);
  out["materials"] = py::array_t<std::int32_t>(static_cast<py::ssize_t>(d.tet_material.size()), d.tet_material.data());
  std::vector<std::array<VertId, 3>> tri;
  std::vector<std::int32_t> tri_refs;
  for (const auto& t : d.triangles) tri.push_back(t.v), tri_refs.push_back(t.ref);
  out["triangles"] = rows<std::int64_t>(tri);
  out["triangle_refs"] = py::array_t<std::int32_t>(static_cast<py::ssize_t>(tri_refs.size()), tri_refs.data());
  std::vector<std::array<VertId, 2>> seg;
  std::vector<std::int32_t> seg_refs;
  for (const auto& s : d.segments) seg.push_back(s.v), seg_refs.push_back(s.ref);
  out["segments"] = rows<std::int64_t>(seg);
  out["segment_refs"] = py::array_t<std::int32_t>(static_cast<py::ssize_t>(seg_refs.size()), seg_refs.data());
  std::vector<std::int64_t> corners(d.corners.begin(), d.corners.end());
  out["corners"] = py::array_t<std::int64_t>(static_cast<py::ssize_t>(corners.size()), corners.data());
  py::dict fields;
  for (const auto& f : d.fields) {
    py::array_t<double> a({static_cast<py::ssize_t>(d.positions.size()), static_cast<py::ssize_t>(f.components)});
    std::copy(f.values.begin(), f.values.end(), a.mutable_data());
    py::object value = a;
    if (f.components == 1) value = a.reshape({static_cast<py::ssize_t>(d.positions.size())});  // a scalar: (n,)
    fields[py::str(f.name)] = value;
  }
  out["fields"] = fields;
  py::dict cell_fields, cell_kinds;
  for (const auto& f : d.cell_fields) {
    const auto m = static_cast<py::ssize_t>(d.tets.size());
    py::array_t<double> a({m, static_cast<py::ssize_t>(f.components)});
    std::copy(f.values.begin(), f.values.end(), a.mutable_data());
    py::object value = a;
    if (f.components == 1) value = a.reshape({m});
    cell_fields[py::str(f.name)] = value;
    cell_kinds[py::str(f.name)] = topotet::cell_kind_name(f.kind);
  }
  out["cell_fields"] = cell_fields;
  out["cell_kinds"] = cell_kinds;
  return out;
}

// Why a run stopped before its target (topotet::StopDiagnosis), as `topotet simplify --json`
// gives it; None when the run reached its target.
py::object stop_dict(const topotet::StopDiagnosis& s) {
  if (!s.is_filled) return py::none();
  py::dict by_reason;
  by_reason["topology"] = s.topology;
  by_reason["pinned"] = s.pinned;
  by_reason["inversion"] = s.inversion;
  by_reason["quality"] = s.quality;
  by_reason["tolerance"] = s.tolerance;
  by_reason["field_error"] = s.field_error;
  by_reason["collapsible"] = s.collapsible;
  py::dict pinned;
  pinned["corners"] = s.pinned_corners;
  pinned["required"] = s.pinned_required;
  pinned["features"] = s.pinned_features;
  pinned["other"] = s.pinned_other;
  py::dict d;
  d["vertices"] = s.vertices;
  d["by_reason"] = by_reason;
  d["pinned_vertices"] = pinned;
  d["dominant"] = std::string(s.dominant);
  d["dominant_share"] = s.dominant_share;
  d["beyond_reach"] = s.beyond_reach;
  d["suggestion"] = s.suggestion;
  return d;
}

topotet::Optimize optimize_of(const std::string& name) {
  if (name == "none") return topotet::Optimize::kNone;
  if (name == "light") return topotet::Optimize::kLight;
  if (name == "full") return topotet::Optimize::kFull;
  throw py::value_error("optimize must be 'none', 'light' or 'full', got '" + name + "'");
}

// The options simplify() and simplify_out_of_core() both take, under the same keywords.
topotet::SimplifyOptions run_options(double ratio, std::uint64_t target_vertices, double tolerance_rel, double tolerance,
                                     double min_quality, double min_dihedral, double size_weight, double max_cost,
                                     int threads, double feature_angle, const std::string& optimize,
                                     double max_field_error, double max_field_error_rel, bool field_bounds,
                                     const std::string& field_bound_mode = "vertices") {
  topotet::SimplifyOptions o;
  if (field_bound_mode == "everywhere")
    o.field_bound_mode = topotet::FieldBoundMode::kEverywhere;
  else if (field_bound_mode != "vertices")
    throw py::value_error("field_bound_mode must be 'vertices' or 'everywhere', got '" + field_bound_mode + "'");
  o.target_vertex_ratio = ratio;
  o.target_vertices = target_vertices;
  o.tolerance_rel = tolerance_rel;
  o.tolerance = tolerance;
  o.min_quality = min_quality;
  o.min_dihedral = min_dihedral;
  o.size_weight = size_weight;
  o.max_cost = max_cost;
  o.num_threads = threads;
  o.feature_angle = feature_angle;
  o.optimize = optimize_of(optimize);
  o.max_field_error = max_field_error;
  o.max_field_error_rel = max_field_error_rel;
  o.track_field_bounds = field_bounds;
  return o;
}

py::dict report_dict(const topotet::Report& r) {
  py::dict rejected;
  for (topotet::RejectReason reason : topotet::kRejectReasons) rejected[topotet::to_string(reason)] = r.rejected_by(reason);
  py::dict phases;
  phases["evaluate"] = r.evaluate_seconds();
  phases["select"] = r.select_seconds();
  phases["apply"] = r.apply_seconds();
  phases["compact"] = r.compact_seconds();
  py::dict d;
  d["status"] = topotet::to_string(r.status);
  d["message"] = r.message;
  d["vertices_before"] = r.vertices_before;
  d["vertices_after"] = r.vertices_after;
  d["tets_before"] = r.tets_before;
  d["tets_after"] = r.tets_after;
  d["collapses"] = r.collapses;
  d["evaluations"] = r.evaluations;
  d["legality_checks"] = r.legality_checks;
  d["rounds"] = r.rounds;
  d["rejected"] = rejected;
  d["seconds"] = r.seconds;
  d["phase_seconds"] = phases;
  d["max_cost"] = r.max_cost;
  d["tolerance"] = r.tolerance;
  d["tolerance_asked"] = r.tolerance_asked;
  d["min_quality_used"] = r.min_quality_used;
  d["min_dihedral_used"] = r.min_dihedral_used;
  d["min_quality_lowest"] = r.min_quality_lowest;  // how far the floors may relax: min(asked, the input's worst)
  d["min_dihedral_lowest"] = r.min_dihedral_lowest;
  py::list relaxations;
  for (const topotet::Relaxation& x : r.relaxations) {
    py::dict step;
    step["limit"] = x.limit;
    step["from"] = x.from;
    step["to"] = x.to;
    step["vertices_left"] = x.vertices_left;
    step["share"] = x.share;
    relaxations.append(step);
  }
  d["relaxations"] = relaxations;
  d["features_dropped"] = r.features_dropped;
  d["stall_flips"] = r.stall_flips;
  d["feature_edges"] = r.feature_edges;
  d["feature_corners"] = r.feature_corners;
  d["optimize_moves"] = r.optimize_moves;
  d["optimize_flips"] = r.optimize_flips;
  d["stopped"] = stop_dict(r.stop);
  // Field error bounds (max_field_error(_rel), field_bounds): the largest bound per component
  // (field units, fields in order) and relative to the range; None when not kept.
  d["field_bound"] = r.field_bounds ? py::cast(r.field_bound) : py::none();
  d["field_bound_rel"] = r.field_bounds ? py::cast(r.field_bound_rel) : py::none();
  d["field_bound_mode"] = r.field_bounds ? py::cast(std::string(topotet::to_string(r.field_bound_mode))) : py::none();
  return d;
}

// Levels as embed_isosurfaces returns them (dicts with field, component, value, ref), or as specs
// "FIELD=VALUE[,VALUE...]" (refs 0: for embed_isosurfaces, which sets them).
std::vector<topotet::IsoLevel> iso_levels(const py::object& obj) {
  std::vector<topotet::IsoLevel> levels;
  if (obj.is_none()) return levels;
  for (const py::handle item : obj) {
    if (py::isinstance<py::str>(item)) {
      if (const std::string why = topotet::parse_isosurface_spec(item.cast<std::string>(), levels); !why.empty())
        throw py::value_error("isosurfaces: " + why);
      continue;
    }
    const py::dict d = item.cast<py::dict>();
    topotet::IsoLevel l;
    l.field = d["field"].cast<std::string>();
    l.component = d.contains("component") ? d["component"].cast<int>() : 0;
    l.value = d["value"].cast<double>();
    l.ref = d.contains("ref") ? d["ref"].cast<std::int32_t>() : 0;
    levels.push_back(l);
  }
  return levels;
}

py::list iso_level_list(const topotet::IsoEmbedReport& report, const topotet::MeshData& d) {
  py::list out;
  for (std::size_t i = 0; i < report.levels.size(); ++i) {
    const topotet::IsoLevel& l = report.levels[i];
    const topotet::IsoLevelStats& s = report.stats[i];
    py::dict e;
    e["field"] = l.field;
    e["component"] = l.component;
    e["value"] = l.value;
    e["ref"] = l.ref;
    for (const topotet::GroupName& g : d.group_names)
      if (g.dim == 2 && g.ref == l.ref) e["name"] = g.name;
    e["triangles"] = s.triangles;
    e["tets_split"] = s.tets_split;
    e["vertices_added"] = s.vertices_added;
    e["vertices_snapped"] = s.vertices_snapped;
    e["seconds"] = s.seconds;
    out.append(e);
  }
  return out;
}

py::dict simplify(const py::object& points, const py::object& tets, const py::object& materials,
                  const py::object& fields, double ratio, std::uint64_t target_vertices, double tolerance_rel,
                  double tolerance, double min_quality, double min_dihedral, double size_weight, double max_cost,
                  int threads, const std::string& engine,
                  const py::object& triangles, const py::object& triangle_refs, const py::object& segments,
                  const py::object& segment_refs, const py::object& corners, double feature_angle,
                  const std::map<std::string, double>& field_weights, double max_field_error,
                  double max_field_error_rel, double boundary_weight, double polyline_weight, double round_fraction,
                  const std::optional<std::string>& hierarchy, const std::string& optimize,
                  const py::object& isosurfaces, const py::object& cell_fields, const py::object& cell_kinds,
                  const std::vector<std::string>& extensive, const std::vector<std::string>& categorical,
                  bool relax_tolerance, bool relax_quality, bool relax_features, bool field_bounds,
                  const std::string& field_bound_mode) {
  std::vector<py::array> keep;
  keep.reserve(4 + (fields.is_none() ? 0 : py::len(fields)));  // the views point into these arrays
  const topotet::MeshView input =
      to_mesh_view(points, tets, materials, triangles, triangle_refs, segments, segment_refs, corners, fields, keep);
  // The cell arrays are carried onto the output by overlap volume (topotet/cell_fields.h), which
  // needs the input's geometry: a copy of points, tets and materials, only when there are any.
  topotet::MeshData original;
  if (!cell_fields.is_none() && py::len(cell_fields) > 0) {
    const py::object none = py::none();
    original = to_mesh_data(points, tets, materials, none, none, none, none, none, none, cell_fields, cell_kinds);
  } else if (!cell_kinds.is_none() && py::len(cell_kinds) > 0) {
    to_cell_fields(cell_fields, cell_kinds, input.tet_count);  // names a kind without an array: the error
  } else if (!extensive.empty() || !categorical.empty()) {
    throw py::value_error("extensive and categorical name cell fields: pass them as cell_fields");
  }
  topotet::CellRemapOptions remap;
  remap.extensive = extensive;
  remap.categorical = categorical;
  topotet::SimplifyOptions options = run_options(ratio, target_vertices, tolerance_rel, tolerance, min_quality, min_dihedral,
                                                  size_weight, max_cost, threads, feature_angle, optimize, max_field_error,
                                                  max_field_error_rel, field_bounds, field_bound_mode);
  options.relax_tolerance = relax_tolerance;
  options.relax_quality = relax_quality;
  options.relax_features = relax_features;
  options.field_weights = field_weights;
  options.boundary_weight = boundary_weight;
  options.polyline_weight = polyline_weight;
  options.round_fraction = round_fraction;
  options.isosurfaces = iso_levels(isosurfaces);
  // As `topotet simplify --hierarchy`: with fields, each collapse records its field error bound, so
  // that extract(max_error=...) selects by a guaranteed error, not by a cost.
  if (hierarchy && !fields.is_none()) options.track_field_bounds = true;
  if (engine == "parallel")
    options.engine = topotet::Engine::kParallel;
  else if (engine == "sequential")
    options.engine = topotet::Engine::kSequential;
  else
    throw py::value_error("engine must be 'parallel' or 'sequential'");
  if (threads < 0) throw py::value_error("threads must be >= 0");
  topotet::Report report;
  topotet::MeshData output;
  std::vector<VertId> map;
  std::optional<topotet::CellRemapReport> remapped;
  {
    py::gil_scoped_release release;
    topotet::TetMesh mesh;
    // The whole call, mesh build included, runs inside the thread limit.
    topotet::run_with_thread_limit(threads, [&] {
      mesh = topotet::TetMesh(std::make_unique<topotet::MeshModel>(topotet::build_mesh_model(input)));
      if (hierarchy) {
        topotet::Hierarchy h;
        report = topotet::simplify_with_hierarchy(mesh, options, h);
        if (report.status == topotet::Status::kOk || report.status == topotet::Status::kStoppedEarly)
          topotet::write_hierarchy(*hierarchy, h);
      } else {
        report = topotet::simplify(mesh, options, map);
      }
    });
    output = mesh.to_mesh_data();
    if (!original.cell_fields.empty() &&
        (report.status == topotet::Status::kOk || report.status == topotet::Status::kStoppedEarly))
      remapped = topotet::remap_cell_fields(original, output, remap);
  }
  if (report.status == topotet::Status::kInvalidInput) throw py::value_error(report.message);
  if (report.status == topotet::Status::kOutOfMemory) throw std::bad_alloc();
  py::dict out = to_dict(output);
  if (hierarchy) {
    out["vertex_map"] = py::none();  // the hierarchy file holds every collapse instead
  } else {
    py::array_t<std::int64_t> vertex_map(static_cast<py::ssize_t>(map.size()));
    auto w = vertex_map.mutable_unchecked<1>();
    for (std::size_t i = 0; i < map.size(); ++i) w(i) = map[i] == topotet::kInvalid ? -1 : std::int64_t{map[i]};
    out["vertex_map"] = vertex_map;
  }
  out["report"] = report_dict(report);
  if (remapped) {
    py::dict r;
    r["overlap_pairs"] = remapped->overlap_pairs;
    r["nearest_new_tets"] = remapped->nearest_new_tets;
    r["nearest_original_tets"] = remapped->nearest_original_tets;
    r["covered_volume_fraction"] = remapped->covered_volume_fraction;
    r["seconds"] = remapped->seconds;
    out["cell_remap"] = r;
  }
  return out;
}

}  // namespace

PYBIND11_MODULE(_core, m) {
  m.doc() = "Topology-preserving simplification of tetrahedral meshes (numpy arrays in and out)";
  m.attr("__version__") = TOPOTET_VERSION_STRING;
  // The library's InputError (bad file, bad mesh) is a ValueError in Python.
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const topotet::InputError& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    }
  });
  // Every default is the library's (SimplifyOptions), so that the same call gives the same run, with
  // the same guarantees, from C++, C, Fortran, Python and the CLI.
  const topotet::SimplifyOptions defaults;
  m.def(
      "default_options",
      [defaults] {
        py::dict d;
        d["ratio"] = defaults.target_vertex_ratio;
        d["target_vertices"] = defaults.target_vertices;
        d["tolerance_rel"] = defaults.tolerance_rel;
        d["tolerance"] = defaults.tolerance;
        d["min_quality"] = defaults.min_quality;
        d["min_dihedral"] = defaults.min_dihedral;
        d["size_weight"] = defaults.size_weight;
        d["max_cost"] = defaults.max_cost;
        d["threads"] = defaults.num_threads;
        d["feature_angle"] = defaults.feature_angle;
        d["max_field_error"] = defaults.max_field_error;
        d["max_field_error_rel"] = defaults.max_field_error_rel;
        d["field_bounds"] = defaults.track_field_bounds;
        d["field_bound_mode"] = topotet::to_string(defaults.field_bound_mode);
        d["boundary_weight"] = defaults.boundary_weight;
        d["polyline_weight"] = defaults.polyline_weight;
        d["round_fraction"] = defaults.round_fraction;
        d["optimize"] = topotet::to_string(defaults.optimize);
        d["relax_tolerance"] = defaults.relax_tolerance;
        d["relax_quality"] = defaults.relax_quality;
        d["relax_features"] = defaults.relax_features;
        return d;
      },
      "The library's SimplifyOptions defaults under simplify()'s keyword names (the keywords' own defaults "
      "are these; python -m topotet --help shows them).");
  m.def("simplify", &simplify, py::arg("points"), py::arg("tets"), py::kw_only(), py::arg("materials") = py::none(),
        py::arg("fields") = py::none(), py::arg("ratio") = defaults.target_vertex_ratio,
        py::arg("target_vertices") = defaults.target_vertices, py::arg("tolerance_rel") = defaults.tolerance_rel,
        py::arg("tolerance") = defaults.tolerance, py::arg("min_quality") = defaults.min_quality,
        py::arg("min_dihedral") = defaults.min_dihedral, py::arg("size_weight") = defaults.size_weight,
        py::arg("max_cost") = defaults.max_cost,
        py::arg("threads") = defaults.num_threads, py::arg("engine") = "parallel", py::arg("triangles") = py::none(),
        py::arg("triangle_refs") = py::none(), py::arg("segments") = py::none(),
        py::arg("segment_refs") = py::none(), py::arg("corners") = py::none(),
        py::arg("feature_angle") = defaults.feature_angle, py::arg("field_weights") = defaults.field_weights,
        py::arg("max_field_error") = defaults.max_field_error, py::arg("max_field_error_rel") = defaults.max_field_error_rel,
        py::arg("boundary_weight") = defaults.boundary_weight, py::arg("polyline_weight") = defaults.polyline_weight,
        py::arg("round_fraction") = defaults.round_fraction, py::arg("hierarchy") = py::none(),
        py::arg("optimize") = topotet::to_string(defaults.optimize), py::arg("isosurfaces") = py::none(),
        py::arg("cell_fields") = py::none(), py::arg("cell_kinds") = py::none(),
        py::arg("extensive") = std::vector<std::string>{}, py::arg("categorical") = std::vector<std::string>{},
        py::arg("relax_tolerance") = defaults.relax_tolerance, py::arg("relax_quality") = defaults.relax_quality,
        py::arg("relax_features") = defaults.relax_features, py::arg("field_bounds") = defaults.track_field_bounds,
        py::arg("field_bound_mode") = topotet::to_string(defaults.field_bound_mode),
        "Simplifies the mesh, keeping its topology and that of every substructure. The options and their "
        "defaults are topotet::SimplifyOptions': the geometric tolerance (tolerance_rel, 0.4% of the diagonal; "
        "0 turns it off; where it would stop the run before its target H doubles unless relax_tolerance=False, and "
        "report['tolerance'] is the H that holds; min_quality and min_dihedral likewise halve unless "
        "relax_quality=False), features at feature_angle degrees (dropped where their corners would stop the run "
        "short, unless relax_features=False) (180 turns them off), field_weights {name: weight}, "
        "field error limits (max_field_error in the field's units, max_field_error_rel relative to its range; "
        "0 = none; field_bounds=True keeps the bounds without a limit; report['field_bound'] / ['field_bound_rel'] "
        "give them; field_bound_mode='everywhere' makes them hold at every point the output covers, not only at the "
        "original vertices, for a price: docs/guarantees.md), optimize ('none', 'light' or 'full': smoothing and flips after the collapses), isosurfaces (the "
        "list embed_isosurfaces returns: the vertices of those levels' triangles keep the level exactly), cell_fields "
        "{name: (m,) or (m, components)} per-tet arrays carried onto the output tets by overlap volume with their "
        "cell_kinds {name: 'intensive' (default) | 'categorical' | 'extensive'} (or the names listed in extensive / "
        "categorical: a sum conserved, a label kept). hierarchy='h.tth' also records every collapse into that file (topotet.extract reads levels "
        "from it; vertex_map is then None). Returns a dict: points, tets, materials, triangles, triangle_refs, segments, segment_refs, "
        "corners, fields, cell_fields, cell_kinds, vertex_map (for every input point, the output point it merged into) and report.");
  m.def(
      "simplify_out_of_core",
      [](const std::string& input, const std::string& output, const py::object& memory_limit, std::uint32_t pieces,
         const std::string& scratch, double ratio, std::uint64_t target_vertices, double tolerance_rel,
         double tolerance, double min_quality, double min_dihedral, double size_weight, double max_cost,
         double feature_angle, int threads, const std::string& optimize, const std::vector<std::string>& extensive,
         const std::vector<std::string>& categorical, const std::string& vertex_map, double max_field_error,
         double max_field_error_rel, bool field_bounds, const std::string& hierarchy, std::uint64_t piece_tets) {
        topotet::OutOfCoreOptions ooc;
        if (py::isinstance<py::str>(memory_limit)) ooc.memory_limit_bytes = topotet::parse_memory_size(memory_limit.cast<std::string>());
        else if (!memory_limit.is_none()) ooc.memory_limit_bytes = memory_limit.cast<std::uint64_t>();
        ooc.pieces = pieces;
        ooc.piece_tets = piece_tets;
        ooc.scratch_parent = scratch;
        ooc.cell_remap.extensive = extensive;
        ooc.cell_remap.categorical = categorical;
        ooc.vertex_map_path = vertex_map;
        ooc.hierarchy_path = hierarchy;
        // As simplify(hierarchy=...): each collapse records its field error bound (a mesh without
        // vertex fields has none).
        const topotet::SimplifyOptions o = run_options(ratio, target_vertices, tolerance_rel, tolerance, min_quality,
                                                       min_dihedral, size_weight, max_cost, threads, feature_angle, optimize,
                                                       max_field_error, max_field_error_rel, field_bounds || !hierarchy.empty());
        topotet::OutOfCoreReport r;
        {
          py::gil_scoped_release release;
          topotet::run_with_thread_limit(threads, [&] { r = topotet::simplify_out_of_core(input, output, o, ooc); });
        }
        py::dict d = report_dict(r.report);
        py::list levels;
        for (const topotet::OutOfCoreLevel& lv : r.levels) {
          py::dict l;
          l["pieces"] = lv.pieces;
          l["pairs_left_apart"] = lv.unmerged;
          l["seams"] = lv.seams;
          l["seams_declined"] = lv.seams_declined;
          l["largest_piece_tets"] = lv.largest_piece_tets;
          l["vertices_after"] = lv.vertices_after;
          l["collapses"] = lv.collapses;
          l["tolerance"] = lv.tolerance;
          l["seconds"] = lv.seconds;
          levels.append(l);
        }
        d["pieces"] = r.pieces;
        d["pieces_left"] = r.output_pieces;
        d["piece_tet_limit"] = r.piece_tet_limit;
        d["levels"] = levels;
        d["peak_rss_bytes"] = r.peak_rss_bytes;
        d["scratch_peak_bytes"] = r.scratch_peak_bytes;
        d["cut_seconds"] = r.cut_seconds;
        d["write_seconds"] = r.write_seconds;
        d["hierarchy_collapses"] = r.hierarchy_collapses;
        d["hierarchy_bytes"] = r.hierarchy_bytes;
        return d;
      },
      py::arg("input"), py::arg("output"), py::kw_only(), py::arg("memory_limit") = py::none(), py::arg("pieces") = 0,
      py::arg("scratch") = "", py::arg("ratio") = defaults.target_vertex_ratio,
      py::arg("target_vertices") = defaults.target_vertices, py::arg("tolerance_rel") = defaults.tolerance_rel,
      py::arg("tolerance") = defaults.tolerance, py::arg("min_quality") = defaults.min_quality,
      py::arg("min_dihedral") = defaults.min_dihedral, py::arg("size_weight") = defaults.size_weight,
      py::arg("max_cost") = defaults.max_cost, py::arg("feature_angle") = defaults.feature_angle,
      py::arg("threads") = defaults.num_threads, py::arg("optimize") = topotet::to_string(defaults.optimize),
      py::arg("extensive") = std::vector<std::string>{}, py::arg("categorical") = std::vector<std::string>{},
      py::arg("vertex_map") = "", py::arg("max_field_error") = defaults.max_field_error,
      py::arg("max_field_error_rel") = defaults.max_field_error_rel, py::arg("field_bounds") = defaults.track_field_bounds,
      py::arg("hierarchy") = "", py::arg("piece_tets") = 0,
      "Simplifies a MEDIT file (.mesh / .meshb, optionally .gz, + .sol / .solb) or a Gmsh MSH 4.1 file with its fields (.msh / .msh.gz) "
      "larger than memory into `output`, out of core "
      "(topotet/out_of_core.h, `topotet simplify --memory-limit`): streamed, cut into pieces in a scratch folder "
      "(next to the output, or in `scratch`), simplified with frozen borders and merged pairwise. memory_limit: "
      "bytes or a size such as '2G' (the peak stays under it; too small is a ValueError before any work); pieces: "
      "exactly this many (a power of two) instead; piece_tets: pieces of at most this many tets, at the cut and in "
      "every merge (tests: what a small limit does on a small mesh; pieces the limit keeps apart at the end are "
      "joined by seams, report['levels'][-1]['seams']). vertex_map: a path (.npy or .txt) to write, for every input "
      "vertex, the output vertex it became or merged into (-1: used by no tet; numpy.load reads the .npy), as "
      "simplify() returns it in core. max_field_error(_rel) and field_bounds as in simplify(): the bound "
      "holds at every input vertex (report['field_bound_rel']). hierarchy='h.tth' records every collapse into that file "
      "as simplify(hierarchy=...) does (on disk during the run; topotet.extract reads levels from it; excludes vertex_map). The topology is not checked here (read both and compare, or "
      "`topotet check IN OUT`). Returns the report dict of simplify() plus pieces, pieces_left, piece_tet_limit, "
      "levels (one dict per level), peak_rss_bytes, scratch_peak_bytes, cut_seconds, write_seconds, hierarchy_collapses, "
      "hierarchy_bytes.");
  m.def(
      "extract",
      [](const std::string& path, std::uint64_t vertices, std::optional<double> max_error) {
        if (vertices > 0 && max_error) throw py::value_error("extract: give vertices or max_error, not both");
        topotet::MeshData d;
        {
          py::gil_scoped_release release;
          const topotet::Hierarchy h = topotet::read_hierarchy(path);
          const std::vector<std::uint8_t> applied =
              max_error ? topotet::select_error(h, *max_error)
                        : topotet::select_prefix(h, vertices > 0 ? topotet::prefix_for_vertices(h, vertices)
                                                                 : h.collapse_count());
          d = topotet::extract(h, applied);
        }
        return to_dict(d);
      },
      py::arg("path"), py::kw_only(), py::arg("vertices") = 0, py::arg("max_error") = py::none(),
      "A level of detail from a hierarchy file (simplify(..., hierarchy=path) or `topotet simplify --hierarchy`): "
      "the mesh with `vertices` vertices (the first collapses), or every collapse whose error is <= max_error "
      "(and whose parents are applied), or, with neither, the simplified mesh itself. Returns a mesh dict.");
  m.def(
      "embed_isosurfaces",
      [](const py::dict& mesh, const py::object& levels, double snap) {
        auto get = [&](const char* key) { return mesh.contains(key) ? py::object(mesh[key]) : py::object(py::none()); };
        if (!mesh.contains("points") || !mesh.contains("tets")) throw py::value_error("the mesh needs 'points' and 'tets'");
        topotet::MeshData d = to_mesh_data(get("points"), get("tets"), get("materials"), get("triangles"),
                                           get("triangle_refs"), get("segments"), get("segment_refs"), get("corners"),
                                           get("fields"), get("cell_fields"), get("cell_kinds"));
        const std::vector<topotet::IsoLevel> wanted = iso_levels(levels);
        topotet::IsoEmbedOptions options;
        options.snap = snap;
        topotet::IsoEmbedReport report;
        {
          py::gil_scoped_release release;
          report = topotet::embed_isosurfaces(d, wanted, options);
        }
        py::dict out = to_dict(d);
        out["isosurfaces"] = iso_level_list(report, d);
        return out;
      },
      py::arg("mesh"), py::arg("levels"), py::kw_only(), py::arg("snap") = topotet::IsoEmbedOptions{}.snap,
      "Splits the tets that the level sets cross so that each becomes a listed surface (topotet/isosurface.h). "
      "levels: specs 'FIELD=VALUE[,VALUE...]' (FIELD may be 'name:component') or dicts {field, component, value}. "
      "Returns the mesh dict with the levels' triangles under new refs, and 'isosurfaces': one dict per level "
      "(field, component, value, ref, name, triangles, tets_split, vertices_added, vertices_snapped, seconds); "
      "pass that list to simplify(isosurfaces=...) so that their vertices keep the level exactly.");
  m.def(
      "read",
      [](const std::string& path) {
        topotet::MeshData d;
        {
          py::gil_scoped_release release;
          d = topotet::read_mesh(path);
        }
        return to_dict(d);
      },
      py::arg("path"), "Reads a .mesh (+.sol), .meshb (+.solb, binary MEDIT) or .msh file (optionally .gz) into a dict of arrays.");
  m.def(
      "write",
      [](const std::string& path, const py::dict& mesh, bool binary) {
        auto get = [&](const char* key) { return mesh.contains(key) ? py::object(mesh[key]) : py::object(py::none()); };
        if (!mesh.contains("points") || !mesh.contains("tets")) throw py::value_error("the mesh needs 'points' and 'tets'");
        const topotet::MeshData d = to_mesh_data(get("points"), get("tets"), get("materials"), get("triangles"),
                                                 get("triangle_refs"), get("segments"), get("segment_refs"),
                                                 get("corners"), get("fields"), get("cell_fields"), get("cell_kinds"));
        py::gil_scoped_release release;
        topotet::write_mesh(path, d, {binary});
      },
      py::arg("path"), py::arg("mesh"), py::kw_only(), py::arg("binary") = false,
      "Writes a mesh dict (as read() or simplify() return; other keys are ignored) to a .mesh, .meshb, .msh or .vtu "
      "file, chosen by the extension.");
  m.def(
      "write_vertex_map",
      [](const std::string& path, const py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>& map) {
        if (map.ndim() != 1) throw py::value_error("write_vertex_map: a one-dimensional array of output vertex indices");
        const auto r = map.unchecked<1>();
        topotet::VertexMapWriter writer(path, static_cast<std::uint64_t>(r.shape(0)));
        for (py::ssize_t i = 0; i < r.shape(0); ++i) {
          if (r(i) < -1) throw py::value_error("write_vertex_map: entry " + std::to_string(i) + " is " + std::to_string(r(i)) + " (an index >= 0, or -1)");
          writer.add(r(i));
        }
        writer.commit();
      },
      py::arg("path"), py::arg("vertex_map"),
      "Writes a vertex map (simplify()'s 'vertex_map') as `topotet simplify --vertex-map` does: .npy (int64) or "
      ".txt (one index per line), atomically.");
  m.def(
      "read_vertex_map",
      [](const std::string& path) {
        const std::vector<std::int64_t> map = topotet::read_vertex_map(path);
        py::array_t<std::int64_t> out(static_cast<py::ssize_t>(map.size()));
        std::copy(map.begin(), map.end(), out.mutable_data());
        return out;
      },
      py::arg("path"), "Reads a vertex map file (.npy or .txt, as write_vertex_map writes it) into an int64 array.");
}
