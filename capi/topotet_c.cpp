// The C API (topotet/topotet_c.h) on the C++ library: strided views are read into a MeshData,
// built into a TetMesh with the non-throwing forms, and no exception crosses the C boundary.
#include "topotet/topotet_c.h"

#include <array>
#include <cmath>
#include <cstring>
#include <exception>
#include <limits>
#include <memory>
#include <new>
#include <string>
#include <tuple>
#include <vector>

#include "mesh/mesh_view.h"
#include "topotet/error.h"
#include "topotet/isosurface.h"
#include "topotet/nothrow.h"
#include "topotet/simplify.h"
#include "topotet/tet_mesh.h"
#include "topotet/threads.h"

struct topotet_mesh {
  topotet::TetMesh mesh;
  std::vector<topotet::VertId> vertex_map;  // of the last simplify
  std::vector<topotet::IsoLevel> isosurfaces;  // embedded so far: every simplify keeps them
  // The listed triangles and segments, recovered from the tet flags on first use after a change.
  mutable std::vector<topotet::Triangle> triangles;
  mutable std::vector<topotet::Segment> segments;
  mutable bool has_substructures = false;

  void recover_substructures() const {
    if (has_substructures) return;
    topotet::MeshData d = mesh.to_mesh_data();
    triangles = std::move(d.triangles);
    segments = std::move(d.segments);
    has_substructures = true;
  }
};

namespace {

using topotet::Status;
using topotet::TetId;
using topotet::VertId;

thread_local std::string last_error;

topotet_status fail(topotet_status status, std::string message) {
  last_error = std::move(message);
  return status;
}

topotet_status to_c(Status s) { return static_cast<topotet_status>(s); }

// Thrown by the view readers and caught at the boundary of each entry point.
struct ArgumentError {
  std::string message;
};

std::size_t type_size(topotet_type t) {
  switch (t) {
    case TOPOTET_FLOAT64: return 8;
    case TOPOTET_FLOAT32: return 4;
    case TOPOTET_INT32: return 4;
    case TOPOTET_INT64: return 8;
  }
  return 0;
}

bool is_integer(topotet_type t) { return t == TOPOTET_INT32 || t == TOPOTET_INT64; }

// Address of value `col` of row `row`; rows are `width` values wide.
const char* at(const topotet_view& v, std::int64_t row, int col, int width) {
  const std::int64_t stride = v.stride != 0 ? v.stride : static_cast<std::int64_t>(width * type_size(v.type));
  return static_cast<const char*>(v.data) + row * stride + static_cast<std::int64_t>(col * type_size(v.type));
}

void check_view(const topotet_view& v, bool integer, const char* what) {
  if (type_size(v.type) == 0) throw ArgumentError{std::string(what) + ": unknown element type"};
  if (is_integer(v.type) != integer)
    throw ArgumentError{std::string(what) + (integer ? ": must be INT32 or INT64" : ": must be FLOAT64 or FLOAT32")};
}

std::int64_t read_int(const topotet_view& v, std::int64_t row, int col, int width) {
  const char* p = at(v, row, col, width);
  if (v.type == TOPOTET_INT32) {
    std::int32_t x;
    std::memcpy(&x, p, sizeof x);
    return x;
  }
  std::int64_t x;
  std::memcpy(&x, p, sizeof x);
  return x;
}

// A vertex index of the caller's numbering -> 0-based; the mesh builder checks the upper bound.
VertId vertex_index(const topotet_view& v, std::int64_t row, int col, int width, int base, const char* what) {
  const std::int64_t x = read_int(v, row, col, width) - base;
  if (x < 0 || x >= static_cast<std::int64_t>(topotet::kInvalid))
    throw ArgumentError{std::string(what) + " " + std::to_string(row) + ": vertex index " + std::to_string(x + base) +
                        " out of range (index_base " + std::to_string(base) + ")"};
  return static_cast<VertId>(x);
}

std::int32_t ref_value(const topotet_view& v, std::int64_t row, const char* what) {
  const std::int64_t x = read_int(v, row, 0, 1);
  if (x < std::numeric_limits<std::int32_t>::min() || x > std::numeric_limits<std::int32_t>::max())
    throw ArgumentError{std::string(what) + " " + std::to_string(row) + ": " + std::to_string(x) + " does not fit in 32 bits"};
  return static_cast<std::int32_t>(x);
}

template <std::size_t N>
std::vector<std::array<VertId, N>> read_cells(const topotet_view& v, std::int64_t count, int base, const char* what) {
  if (count == 0) return {};
  check_view(v, true, what);
  std::vector<std::array<VertId, N>> out(static_cast<std::size_t>(count));
  for (std::int64_t r = 0; r < count; ++r)
    for (int c = 0; c < static_cast<int>(N); ++c) out[r][c] = vertex_index(v, r, c, N, base, what);
  return out;
}

std::vector<std::int32_t> read_refs(const topotet_view& v, std::int64_t count, const char* what) {
  std::vector<std::int32_t> out;
  if (v.data == nullptr || count == 0) return out;
  check_view(v, true, what);
  out.resize(static_cast<std::size_t>(count));
  for (std::int64_t r = 0; r < count; ++r) out[r] = ref_value(v, r, what);
  return out;
}

topotet::StridedArray strided(const topotet_view& v) {
  static constexpr topotet::StridedArray::Type kTypes[] = {
      topotet::StridedArray::Type::kFloat64, topotet::StridedArray::Type::kFloat32,
      topotet::StridedArray::Type::kInt32, topotet::StridedArray::Type::kInt64};
  const bool known = type_size(v.type) != 0;  // an unknown type was refused or is never read
  return {v.data, known ? kTypes[v.type] : topotet::StridedArray::Type::kFloat64, v.stride, 0};
}

// The caller's arrays as the engine's views: positions, tets, materials, vertex refs and fields are
// read in place by the builder, straight into the model (no intermediate MeshData). The listed
// triangles, segments and corners, small next to the volume, are converted here.
topotet::MeshView to_mesh_view(const topotet_mesh_arrays& a) {
  if (a.index_base != 0 && a.index_base != 1) throw ArgumentError{"index_base must be 0 or 1"};
  if (a.vertex_count < 0 || a.tet_count < 0 || a.triangle_count < 0 || a.segment_count < 0 || a.corner_count < 0 ||
      a.field_count < 0)
    throw ArgumentError{"negative count"};
  if (a.positions.data == nullptr && a.vertex_count > 0) throw ArgumentError{"positions not given"};
  if (a.tets.data == nullptr && a.tet_count > 0) throw ArgumentError{"tets not given"};
  auto needs = [](std::int64_t count, const topotet_view& v, const char* what) {
    if (count > 0 && v.data == nullptr) throw ArgumentError{std::string(what) + " not given"};
  };
  needs(a.triangle_count, a.triangles, "triangles");
  needs(a.segment_count, a.segments, "segments");
  needs(a.corner_count, a.corners, "corners");
  topotet::MeshView d;
  check_view(a.positions, false, "positions");
  d.vertex_count = static_cast<std::size_t>(a.vertex_count);
  d.positions = strided(a.positions);
  if (a.tet_count > 0) check_view(a.tets, true, "tet");
  d.tet_count = static_cast<std::size_t>(a.tet_count);
  d.tets = strided(a.tets);
  d.index_base = a.index_base;
  if (a.materials.data != nullptr && a.tet_count > 0) {
    check_view(a.materials, true, "material of tet");
    d.materials = strided(a.materials);
  }
  if (a.vertex_refs.data != nullptr && a.vertex_count > 0) {
    check_view(a.vertex_refs, true, "ref of vertex");
    d.vertex_refs = strided(a.vertex_refs);
  }
  const auto triangles = read_cells<3>(a.triangles, a.triangle_count, a.index_base, "triangle");
  const auto triangle_refs = read_refs(a.triangle_refs, a.triangle_count, "ref of triangle");
  for (std::size_t i = 0; i < triangles.size(); ++i)
    d.triangles.push_back({triangles[i], triangle_refs.empty() ? 0 : triangle_refs[i]});
  const auto segments = read_cells<2>(a.segments, a.segment_count, a.index_base, "segment");
  const auto segment_refs = read_refs(a.segment_refs, a.segment_count, "ref of segment");
  for (std::size_t i = 0; i < segments.size(); ++i)
    d.segments.push_back({segments[i], segment_refs.empty() ? 0 : segment_refs[i]});
  for (const auto& c : read_cells<1>(a.corners, a.corner_count, a.index_base, "corner")) d.corners.push_back(c[0]);
  if (a.field_count > 0 && a.fields == nullptr) throw ArgumentError{"fields not given"};
  for (int f = 0; f < a.field_count; ++f) {
    const topotet_field_view& fv = a.fields[f];
    const std::string name = fv.name != nullptr ? fv.name : "field" + std::to_string(f);
    if (fv.components < 1) throw ArgumentError{"field " + name + ": components must be >= 1"};
    if (fv.values.data == nullptr) throw ArgumentError{"field " + name + ": values not given"};
    check_view(fv.values, false, "field values");
    d.fields.push_back({name, fv.components, strided(fv.values)});
  }
  return d;
}

// Runs an entry point's body; exceptions become a status and the thread's last error.
template <class F>
topotet_status guarded(F&& body) noexcept {
  try {
    return body();
  } catch (const ArgumentError& e) {
    return fail(TOPOTET_INVALID_INPUT, e.message);
  } catch (const topotet::InputError& e) {
    return fail(TOPOTET_INVALID_INPUT, e.what());
  } catch (const std::bad_alloc&) {
    return fail(TOPOTET_OUT_OF_MEMORY, "out of memory");
  } catch (const std::exception& e) {
    return fail(TOPOTET_INTERNAL_ERROR, std::string("internal error: ") + e.what());
  } catch (...) {
    return fail(TOPOTET_INTERNAL_ERROR, "internal error: unknown exception");
  }
}

void write_int(const topotet_out_view& v, std::int64_t row, int col, int width, std::int64_t x) {
  const std::int64_t stride = v.stride != 0 ? v.stride : static_cast<std::int64_t>(width * type_size(v.type));
  char* p = static_cast<char*>(v.data) + row * stride + static_cast<std::int64_t>(col * type_size(v.type));
  if (v.type == TOPOTET_INT32) {
    const auto y = static_cast<std::int32_t>(x);
    std::memcpy(p, &y, sizeof y);
  } else {
    std::memcpy(p, &x, sizeof x);
  }
}

void write_real(const topotet_out_view& v, std::int64_t row, int col, int width, double x) {
  const std::int64_t stride = v.stride != 0 ? v.stride : static_cast<std::int64_t>(width * type_size(v.type));
  char* p = static_cast<char*>(v.data) + row * stride + static_cast<std::int64_t>(col * type_size(v.type));
  if (v.type == TOPOTET_FLOAT32) {
    const auto y = static_cast<float>(x);
    std::memcpy(p, &y, sizeof y);
  } else {
    std::memcpy(p, &x, sizeof x);
  }
}

topotet_status check_out(const topotet_mesh* mesh, const topotet_out_view& v, bool integer, const char* what) {
  if (mesh == nullptr) return fail(TOPOTET_INVALID_INPUT, std::string(what) + ": mesh is NULL");
  if (v.data == nullptr) return fail(TOPOTET_INVALID_INPUT, std::string(what) + ": output array is NULL");
  if (type_size(v.type) == 0 || is_integer(v.type) != integer)
    return fail(TOPOTET_INVALID_INPUT,
                std::string(what) + (integer ? ": output must be INT32 or INT64" : ": output must be FLOAT64 or FLOAT32"));
  return TOPOTET_OK;
}

template <class Item>
topotet_status copy_items(const topotet_mesh* mesh, const std::vector<Item>& items, topotet_out_view out,
                          topotet_out_view refs_out, int index_base, const char* what) {
  if (const topotet_status s = check_out(mesh, out, true, what); s != TOPOTET_OK) return s;
  if (refs_out.data != nullptr && !is_integer(refs_out.type))
    return fail(TOPOTET_INVALID_INPUT, std::string(what) + ": refs output must be INT32 or INT64");
  if (index_base != 0 && index_base != 1) return fail(TOPOTET_INVALID_INPUT, "index_base must be 0 or 1");
  constexpr int n = static_cast<int>(std::tuple_size_v<decltype(Item::v)>);
  for (std::size_t i = 0; i < items.size(); ++i) {
    for (int c = 0; c < n; ++c) write_int(out, static_cast<std::int64_t>(i), c, n, std::int64_t{items[i].v[c]} + index_base);
    if (refs_out.data != nullptr) write_int(refs_out, static_cast<std::int64_t>(i), 0, 1, items[i].ref);
  }
  return TOPOTET_OK;
}

}  // namespace

extern "C" {

const char* topotet_version(void) { return TOPOTET_VERSION_STRING; }
const char* topotet_last_error(void) { return last_error.c_str(); }
const char* topotet_status_string(topotet_status status) {
  if (status < TOPOTET_OK || status > TOPOTET_INTERNAL_ERROR) return "unknown";
  return topotet::to_string(static_cast<Status>(status));
}

void topotet_mesh_arrays_init(topotet_mesh_arrays* arrays) {
  if (arrays != nullptr) *arrays = topotet_mesh_arrays{};
}

void topotet_options_init(topotet_options* options) {
  if (options == nullptr) return;
  const topotet::SimplifyOptions d;
  *options = topotet_options{};
  options->target_vertex_ratio = d.target_vertex_ratio;
  options->target_vertices = static_cast<std::int64_t>(d.target_vertices);
  options->max_cost = d.max_cost;
  options->min_quality = d.min_quality;
  options->boundary_weight = d.boundary_weight;
  options->polyline_weight = d.polyline_weight;
  options->tolerance = d.tolerance;
  options->tolerance_rel = d.tolerance_rel;
  options->engine = static_cast<int>(d.engine);
  options->num_threads = d.num_threads;
  options->round_fraction = d.round_fraction;
  options->feature_angle = d.feature_angle;
  options->max_field_error = d.max_field_error;
  options->max_field_error_rel = d.max_field_error_rel;
  options->field_weight_count = 0;
  options->field_weight_names = nullptr;
  options->field_weights = nullptr;
  options->optimize = static_cast<int>(d.optimize);
}

topotet_status topotet_mesh_build(const topotet_mesh_arrays* arrays, int num_threads, topotet_mesh** mesh) {
  return guarded([&] {
    if (arrays == nullptr || mesh == nullptr) return fail(TOPOTET_INVALID_INPUT, "topotet_mesh_build: NULL argument");
    *mesh = nullptr;
    if (num_threads < 0) return fail(TOPOTET_INVALID_INPUT, "num_threads must be >= 0");
    const topotet::MeshView view = to_mesh_view(*arrays);
    auto result = std::make_unique<topotet_mesh>();
    topotet::run_with_thread_limit(num_threads, [&] {
      result->mesh = topotet::TetMesh(std::make_unique<topotet::MeshModel>(topotet::build_mesh_model(view)));
    });
    *mesh = result.release();
    return TOPOTET_OK;
  });
}

topotet_status topotet_mesh_read(const char* path, int num_threads, topotet_mesh** mesh) {
  return guarded([&] {
    if (path == nullptr || mesh == nullptr) return fail(TOPOTET_INVALID_INPUT, "topotet_mesh_read: NULL argument");
    *mesh = nullptr;
    topotet::MeshData data;
    std::string message;
    Status s = topotet::try_read_mesh(path, data, message);
    if (s != Status::kOk) return fail(to_c(s), message);
    auto result = std::make_unique<topotet_mesh>();
    s = topotet::try_build_tet_mesh(data, result->mesh, message, {}, num_threads);
    if (s != Status::kOk) return fail(to_c(s), std::string(path) + ": " + message);
    *mesh = result.release();
    return TOPOTET_OK;
  });
}

topotet_status topotet_mesh_write(const topotet_mesh* mesh, const char* path) {
  return guarded([&] {
    if (path == nullptr || mesh == nullptr) return fail(TOPOTET_INVALID_INPUT, "topotet_mesh_write: NULL argument");
    std::string message;
    const Status s = topotet::try_write_mesh(path, mesh->mesh.to_mesh_data(), message);
    return s == Status::kOk ? TOPOTET_OK : fail(to_c(s), message);
  });
}

void topotet_mesh_free(topotet_mesh* mesh) { delete mesh; }

topotet_status topotet_mesh_embed_isosurfaces(topotet_mesh* mesh, const char* field, int component, const double* values,
                                              int count, double snap, int32_t* refs_out) {
  return guarded([&] {
    if (mesh == nullptr || field == nullptr || (count > 0 && values == nullptr))
      return fail(TOPOTET_INVALID_INPUT, "topotet_mesh_embed_isosurfaces: NULL argument");
    if (count < 0) return fail(TOPOTET_INVALID_INPUT, "topotet_mesh_embed_isosurfaces: count must be >= 0");
    std::vector<topotet::IsoLevel> levels;
    for (int i = 0; i < count; ++i) levels.push_back({field, component, values[i], 0});
    topotet::IsoEmbedOptions embed;
    if (snap >= 0.0) embed.snap = snap;
    // On a copy: a refused level (unknown field, ...) leaves the mesh as it was.
    topotet::MeshData data = mesh->mesh.to_mesh_data();
    const topotet::IsoEmbedReport embedded = topotet::embed_isosurfaces(data, levels, embed);
    topotet::TetMesh rebuilt = topotet::build_tet_mesh(data);
    mesh->mesh = std::move(rebuilt);
    mesh->vertex_map.clear();
    mesh->has_substructures = false;
    for (std::size_t i = 0; i < embedded.levels.size(); ++i) {
      mesh->isosurfaces.push_back(embedded.levels[i]);
      if (refs_out != nullptr) refs_out[i] = embedded.levels[i].ref;
    }
    return TOPOTET_OK;
  });
}

topotet_status topotet_simplify(topotet_mesh* mesh, const topotet_options* options, topotet_report* report) {
  return guarded([&] {
    if (mesh == nullptr) return fail(TOPOTET_INVALID_INPUT, "topotet_simplify: mesh is NULL");
    topotet_options c;
    topotet_options_init(&c);
    if (options != nullptr) c = *options;
    if (c.target_vertices < 0) return fail(TOPOTET_INVALID_INPUT, "target_vertices must be >= 0");
    if (c.engine != 0 && c.engine != 1) return fail(TOPOTET_INVALID_INPUT, "engine must be 0 (parallel) or 1 (sequential)");
    topotet::SimplifyOptions o;
    o.target_vertex_ratio = c.target_vertex_ratio;
    o.target_vertices = static_cast<std::uint64_t>(c.target_vertices);
    o.max_cost = c.max_cost;
    o.min_quality = c.min_quality;
    o.boundary_weight = c.boundary_weight;
    o.polyline_weight = c.polyline_weight;
    o.tolerance = c.tolerance;
    o.tolerance_rel = c.tolerance_rel;
    o.engine = static_cast<topotet::Engine>(c.engine);
    o.num_threads = c.num_threads;
    o.round_fraction = c.round_fraction;
    o.feature_angle = c.feature_angle;
    o.max_field_error = c.max_field_error;
    o.max_field_error_rel = c.max_field_error_rel;
    if (c.optimize < 0 || c.optimize > 2) return fail(TOPOTET_INVALID_INPUT, "optimize must be 0 (none), 1 (light) or 2 (full)");
    o.optimize = static_cast<topotet::Optimize>(c.optimize);
    if (c.field_weight_count < 0) return fail(TOPOTET_INVALID_INPUT, "field_weight_count must be >= 0");
    if (c.field_weight_count > 0 && (c.field_weight_names == nullptr || c.field_weights == nullptr))
      return fail(TOPOTET_INVALID_INPUT, "field_weight_names and field_weights must not be NULL when field_weight_count > 0");
    for (int i = 0; i < c.field_weight_count; ++i) {
      if (c.field_weight_names[i] == nullptr) return fail(TOPOTET_INVALID_INPUT, "field_weight_names has a NULL entry");
      o.field_weights[c.field_weight_names[i]] = c.field_weights[i];  // the library checks names and values
    }
    o.isosurfaces = mesh->isosurfaces;
    mesh->has_substructures = false;
    const topotet::Report r = topotet::simplify(mesh->mesh, o, mesh->vertex_map);
    if (report != nullptr) {
      *report = topotet_report{};
      report->status = to_c(r.status);
      report->vertices_before = static_cast<std::int64_t>(r.vertices_before);
      report->vertices_after = static_cast<std::int64_t>(r.vertices_after);
      report->tets_before = static_cast<std::int64_t>(r.tets_before);
      report->tets_after = static_cast<std::int64_t>(r.tets_after);
      report->collapses = static_cast<std::int64_t>(r.collapses);
      report->evaluations = static_cast<std::int64_t>(r.evaluations);
      report->legality_checks = static_cast<std::int64_t>(r.legality_checks);
      report->rounds = static_cast<std::int64_t>(r.rounds);
      using topotet::RejectReason;
      report->rejected_link_k = static_cast<std::int64_t>(r.rejected_by(RejectReason::kLinkK));
      report->rejected_link_ktilde = static_cast<std::int64_t>(r.rejected_by(RejectReason::kLinkKtilde));
      report->rejected_pinned = static_cast<std::int64_t>(r.rejected_by(RejectReason::kPinned));
      report->rejected_inversion = static_cast<std::int64_t>(r.rejected_by(RejectReason::kInversion));
      report->rejected_quality = static_cast<std::int64_t>(r.rejected_by(RejectReason::kQuality));
      report->rejected_tolerance = static_cast<std::int64_t>(r.rejected_by(RejectReason::kTolerance));
      report->seconds = r.seconds;
      report->max_cost = r.max_cost;
      report->tolerance = r.tolerance;
      report->rejected_field_error = static_cast<std::int64_t>(r.rejected_by(RejectReason::kFieldError));
      report->feature_edges = static_cast<std::int64_t>(r.feature_edges);
      report->feature_corners = static_cast<std::int64_t>(r.feature_corners);
      report->optimize_moves = static_cast<std::int64_t>(r.optimize_moves);
      report->optimize_flips = static_cast<std::int64_t>(r.optimize_flips);
      if (r.stop.is_filled) {
        const topotet::StopDiagnosis& d = r.stop;
        const auto i64 = [](std::uint64_t x) { return static_cast<std::int64_t>(x); };
        report->stop_vertices = i64(d.vertices);
        report->held_topology = i64(d.topology);
        report->held_pinned = i64(d.pinned);
        report->held_inversion = i64(d.inversion);
        report->held_quality = i64(d.quality);
        report->held_tolerance = i64(d.tolerance);
        report->held_field_error = i64(d.field_error);
        report->held_collapsible = i64(d.collapsible);
        report->pinned_corners = i64(d.pinned_corners);
        report->pinned_required = i64(d.pinned_required);
        report->pinned_features = i64(d.pinned_features);
        report->pinned_other = i64(d.pinned_other);
        report->stop_dominant_share = d.dominant_share;
        std::snprintf(report->stop_dominant, sizeof report->stop_dominant, "%s", d.dominant);
        std::snprintf(report->stop_suggestion, sizeof report->stop_suggestion, "%s", d.suggestion.c_str());
      }
    }
    const topotet_status s = to_c(r.status);
    if (s != TOPOTET_OK && s != TOPOTET_STOPPED_EARLY) return fail(s, r.message);
    return s;
  });
}

int64_t topotet_mesh_vertex_count(const topotet_mesh* mesh) {
  return mesh != nullptr ? static_cast<std::int64_t>(mesh->mesh.vertex_capacity()) : 0;
}
int64_t topotet_mesh_tet_count(const topotet_mesh* mesh) {
  return mesh != nullptr ? static_cast<std::int64_t>(mesh->mesh.tet_capacity()) : 0;
}
int topotet_mesh_field_count(const topotet_mesh* mesh) {
  return mesh != nullptr ? static_cast<int>(mesh->mesh.fields().size()) : 0;
}
int64_t topotet_mesh_vertex_map_size(const topotet_mesh* mesh) {
  return mesh != nullptr ? static_cast<std::int64_t>(mesh->vertex_map.size()) : 0;
}

topotet_status topotet_mesh_field_info(const topotet_mesh* mesh, int i, const char** name, int* components) {
  if (mesh == nullptr || i < 0 || i >= static_cast<int>(mesh->mesh.fields().size()))
    return fail(TOPOTET_INVALID_INPUT, "topotet_mesh_field_info: no field " + std::to_string(i));
  if (name != nullptr) *name = mesh->mesh.fields()[i].name.c_str();
  if (components != nullptr) *components = mesh->mesh.fields()[i].components;
  return TOPOTET_OK;
}

const double* topotet_mesh_positions(const topotet_mesh* mesh) {
  return mesh != nullptr ? mesh->mesh.positions_data() : nullptr;
}
const uint32_t* topotet_mesh_tets(const topotet_mesh* mesh) { return mesh != nullptr ? mesh->mesh.tets_data() : nullptr; }
const int32_t* topotet_mesh_materials(const topotet_mesh* mesh) {
  return mesh != nullptr ? mesh->mesh.materials_data() : nullptr;
}
const uint32_t* topotet_mesh_vertex_map(const topotet_mesh* mesh) {
  return mesh != nullptr && !mesh->vertex_map.empty() ? mesh->vertex_map.data() : nullptr;
}

topotet_status topotet_mesh_copy_positions(const topotet_mesh* mesh, topotet_out_view out) {
  if (const topotet_status s = check_out(mesh, out, false, "positions"); s != TOPOTET_OK) return s;
  const double* p = mesh->mesh.positions_data();
  for (std::size_t v = 0; v < mesh->mesh.vertex_capacity(); ++v)
    for (int c = 0; c < 3; ++c) write_real(out, static_cast<std::int64_t>(v), c, 3, p[3 * v + c]);
  return TOPOTET_OK;
}

topotet_status topotet_mesh_copy_tets(const topotet_mesh* mesh, topotet_out_view out, int index_base) {
  if (const topotet_status s = check_out(mesh, out, true, "tets"); s != TOPOTET_OK) return s;
  if (index_base != 0 && index_base != 1) return fail(TOPOTET_INVALID_INPUT, "index_base must be 0 or 1");
  const VertId* t = mesh->mesh.tets_data();
  for (std::size_t i = 0; i < mesh->mesh.tet_capacity(); ++i)
    for (int c = 0; c < 4; ++c) write_int(out, static_cast<std::int64_t>(i), c, 4, std::int64_t{t[4 * i + c]} + index_base);
  return TOPOTET_OK;
}

topotet_status topotet_mesh_copy_materials(const topotet_mesh* mesh, topotet_out_view out) {
  if (const topotet_status s = check_out(mesh, out, true, "materials"); s != TOPOTET_OK) return s;
  for (std::size_t i = 0; i < mesh->mesh.tet_capacity(); ++i)
    write_int(out, static_cast<std::int64_t>(i), 0, 1, mesh->mesh.material(static_cast<TetId>(i)));
  return TOPOTET_OK;
}

topotet_status topotet_mesh_copy_field(const topotet_mesh* mesh, int i, topotet_out_view out) {
  if (const topotet_status s = check_out(mesh, out, false, "field"); s != TOPOTET_OK) return s;
  const auto& fields = mesh->mesh.fields();
  if (i < 0 || i >= static_cast<int>(fields.size()))
    return fail(TOPOTET_INVALID_INPUT, "topotet_mesh_copy_field: no field " + std::to_string(i));
  int offset = 0;
  for (int k = 0; k < i; ++k) offset += fields[k].components;
  const int stride = mesh->mesh.field_stride(), n = fields[i].components;
  for (std::size_t v = 0; v < mesh->mesh.vertex_capacity(); ++v)
    for (int c = 0; c < n; ++c)
      write_real(out, static_cast<std::int64_t>(v), c, n, mesh->mesh.field_values_data()[v * stride + offset + c]);
  return TOPOTET_OK;
}

topotet_status topotet_mesh_copy_vertex_map(const topotet_mesh* mesh, topotet_out_view out, int index_base) {
  if (const topotet_status s = check_out(mesh, out, true, "vertex map"); s != TOPOTET_OK) return s;
  if (index_base != 0 && index_base != 1) return fail(TOPOTET_INVALID_INPUT, "index_base must be 0 or 1");
  const auto& map = mesh->vertex_map;
  // An input vertex that no tet used has no image: -1 in either numbering.
  for (std::size_t i = 0; i < map.size(); ++i)
    write_int(out, static_cast<std::int64_t>(i), 0, 1, map[i] == topotet::kInvalid ? -1 : std::int64_t{map[i]} + index_base);
  return TOPOTET_OK;
}

}  // extern "C"

namespace {
// The count of the listed triangles or segments (`items` picks which), recovered on first use:
// 0 for a NULL mesh, -1 (and the error set) when out of memory.
template <class Items>
int64_t substructure_count(const topotet_mesh* mesh, Items items) {
  if (mesh == nullptr) return 0;
  try {
    mesh->recover_substructures();
  } catch (const std::bad_alloc&) {
    fail(TOPOTET_OUT_OF_MEMORY, "out of memory");
    return -1;
  }
  return static_cast<std::int64_t>(items(*mesh).size());
}
}  // namespace

extern "C" {

int64_t topotet_mesh_triangle_count(const topotet_mesh* mesh) {
  return substructure_count(mesh, [](const topotet_mesh& m) -> const auto& { return m.triangles; });
}

int64_t topotet_mesh_segment_count(const topotet_mesh* mesh) {
  return substructure_count(mesh, [](const topotet_mesh& m) -> const auto& { return m.segments; });
}


topotet_status topotet_mesh_copy_triangles(const topotet_mesh* mesh, topotet_out_view out, topotet_out_view refs_out,
                                           int index_base) {
  return guarded([&] {
    if (mesh == nullptr) return fail(TOPOTET_INVALID_INPUT, "triangles: mesh is NULL");
    mesh->recover_substructures();
    return copy_items(mesh, mesh->triangles, out, refs_out, index_base, "triangles");
  });
}

topotet_status topotet_mesh_copy_segments(const topotet_mesh* mesh, topotet_out_view out, topotet_out_view refs_out,
                                          int index_base) {
  return guarded([&] {
    if (mesh == nullptr) return fail(TOPOTET_INVALID_INPUT, "segments: mesh is NULL");
    mesh->recover_substructures();
    return copy_items(mesh, mesh->segments, out, refs_out, index_base, "segments");
  });
}

}  // extern "C"
