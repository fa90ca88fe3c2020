// The C API (topotet/topotet_c.h) on the C++ library: strided views are read into a MeshData,
// built into a TetMesh with the non-throwing forms, and no exception crosses the C boundary.
#include "topotet/topotet_c.h"

#include <array>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <limits>
#include <memory>
#include <new>
#include <string>
#include <tuple>
#include <type_traits>
#include <vector>

#include "mesh/mesh_view.h"
#include "topotet/cell_fields.h"
#include "topotet/error.h"
#include "topotet/isosurface.h"
#include "topotet/nothrow.h"
#include "topotet/out_of_core.h"
#include "topotet/simplify.h"
#include "topotet/tet_mesh.h"
#include "topotet/threads.h"

struct topotet_mesh {
  topotet::TetMesh mesh;
  std::vector<topotet::VertId> vertex_map;  // of the last simplify
  std::vector<topotet::IsoLevel> isosurfaces;  // embedded so far: every simplify keeps them
  // Per-tet arrays, aligned with the current tets (empty: none, and no cost). A simplify remaps
  // them from a copy of the geometry as it was before the call, made only when there are any.
  std::vector<topotet::CellField> cell_fields;
  std::vector<double> field_bound;  // of the last simplify that kept the field error bounds
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

// The value a caller stored in an enum member, read without loading the enum: a value outside the
// enumerators is undefined behaviour in C++ (UBSan's -fsanitize=enum), and the message says it.
template <class E>
int stored_value(const E& e) {
  std::underlying_type_t<E> x;
  std::memcpy(&x, &e, sizeof x);
  return static_cast<int>(x);
}

// 0 for a value that is no element type (the views' checks refuse it before any read). Both take
// the member itself, read as stored: the caller's struct may hold any integer there.
std::size_t type_size(const topotet_type& member) {
  switch (stored_value(member)) {
    case TOPOTET_FLOAT64: return 8;
    case TOPOTET_FLOAT32: return 4;
    case TOPOTET_INT32: return 4;
    case TOPOTET_INT64: return 8;
  }
  return 0;
}

bool is_integer(const topotet_type& member) {
  const int t = stored_value(member);
  return t == TOPOTET_INT32 || t == TOPOTET_INT64;
}

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

// One caller's cell array, checked and converted to doubles; `index` names it when it has no name.
// Tets and components are counted from 1 in the messages, as in the builder's.
// `taken` are the names already present (a duplicate is an error).
topotet::CellField read_cell_field(const topotet_cell_field_view& v, int index, std::int64_t tet_count,
                                   const std::vector<topotet::CellField>& taken) {
  topotet::CellField f;
  f.name = v.name != nullptr ? v.name : "cell" + std::to_string(index);
  const std::string what = "cell array '" + f.name + "'";
  for (const topotet::CellField& g : taken)
    if (g.name == f.name) throw ArgumentError{what + ": the name is given twice"};
  if (v.components < 1) throw ArgumentError{what + ": components must be >= 1, got " + std::to_string(v.components)};
  switch (const int kind = stored_value(v.kind)) {
    case TOPOTET_CELL_INTENSIVE: f.kind = topotet::CellFieldKind::kIntensive; break;
    case TOPOTET_CELL_CATEGORICAL: f.kind = topotet::CellFieldKind::kCategorical; break;
    case TOPOTET_CELL_EXTENSIVE: f.kind = topotet::CellFieldKind::kExtensive; break;
    default:
      throw ArgumentError{what + ": unknown kind " + std::to_string(kind) + " (0 intensive, 1 categorical, 2 extensive)"};
  }
  f.components = v.components;
  if (tet_count == 0) return f;
  if (v.values.data == nullptr) throw ArgumentError{what + ": values not given"};
  if (const int type = stored_value(v.values.type); type < TOPOTET_FLOAT64 || type > TOPOTET_INT64)
    throw ArgumentError{what + ": unknown element type " + std::to_string(type)};
  f.values.resize(static_cast<std::size_t>(tet_count) * static_cast<std::size_t>(v.components));
  constexpr std::int64_t kExact = std::int64_t{1} << 53;  // integers a double holds exactly
  for (std::int64_t t = 0; t < tet_count; ++t)
    for (int c = 0; c < v.components; ++c) {
      double x;
      const char* p = at(v.values, t, c, v.components);
      if (is_integer(v.values.type)) {
        const std::int64_t i = read_int(v.values, t, c, v.components);
        if (i > kExact || i < -kExact)
          throw ArgumentError{what + ": value " + std::to_string(i) + " of tet " + std::to_string(t + 1) +
                              " does not fit in a double exactly"};
        x = static_cast<double>(i);
      } else if (v.values.type == TOPOTET_FLOAT32) {
        float y;
        std::memcpy(&y, p, sizeof y);
        x = y;
      } else {
        std::memcpy(&x, p, sizeof x);
      }
      if (!std::isfinite(x))
        throw ArgumentError{what + ": value " + std::to_string(x) + " of tet " + std::to_string(t + 1) + ", component " +
                            std::to_string(c + 1) + " is not finite"};
      f.values[static_cast<std::size_t>(t) * static_cast<std::size_t>(v.components) + static_cast<std::size_t>(c)] = x;
    }
  return f;
}

std::vector<topotet::CellField> read_cell_fields(const topotet_mesh_arrays& a) {
  std::vector<topotet::CellField> out;
  if (a.cell_field_count < 0) throw ArgumentError{"cell_field_count must be >= 0"};
  if (a.cell_field_count > 0 && a.cell_fields == nullptr) throw ArgumentError{"cell_fields not given"};
  for (int i = 0; i < a.cell_field_count; ++i) out.push_back(read_cell_field(a.cell_fields[i], i, a.tet_count, out));
  return out;
}

// The geometry the cell remap needs (positions, tets, materials) of the current mesh, without its
// substructures. The handle's meshes are compact: every tet up to tet_capacity is live.
topotet::MeshData remap_geometry(const topotet::TetMesh& m) {
  topotet::MeshData d;
  const std::size_t nv = m.vertex_capacity(), nt = m.tet_capacity();
  d.positions.resize(nv);
  if (nv > 0) std::memcpy(d.positions.data(), m.positions_data(), nv * sizeof d.positions[0]);
  d.tets.resize(nt);
  if (nt > 0) {
    std::memcpy(d.tets.data(), m.tets_data(), nt * sizeof d.tets[0]);
    d.tet_material.assign(m.materials_data(), m.materials_data() + nt);
  }
  return d;
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
  if (arrays != nullptr) *arrays = topotet_mesh_arrays{};  // cell_field_count 0, cell_fields NULL
}

void topotet_options_init(topotet_options* options) {
  if (options == nullptr) return;
  const topotet::SimplifyOptions d;
  *options = topotet_options{};
  options->target_vertex_ratio = d.target_vertex_ratio;
  options->target_vertices = static_cast<std::int64_t>(d.target_vertices);
  options->max_cost = d.max_cost;
  options->min_quality = d.min_quality;
  options->min_dihedral = d.min_dihedral;
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
  options->track_field_bounds = d.track_field_bounds ? 1 : 0;
  options->field_bound_mode = static_cast<int>(d.field_bound_mode);
  options->progress = nullptr;  // d.on_progress is empty
  options->progress_user_data = nullptr;
  options->size_weight = d.size_weight;
  options->relax_tolerance = d.relax_tolerance ? 1 : 0;
  options->relax_quality = d.relax_quality ? 1 : 0;
  options->relax_features = d.relax_features ? 1 : 0;
}

topotet_status topotet_mesh_build(const topotet_mesh_arrays* arrays, int num_threads, topotet_mesh** mesh) {
  return guarded([&] {
    if (arrays == nullptr || mesh == nullptr) return fail(TOPOTET_INVALID_INPUT, "topotet_mesh_build: NULL argument");
    *mesh = nullptr;
    if (num_threads < 0) return fail(TOPOTET_INVALID_INPUT, "num_threads must be >= 0");
    const topotet::MeshView view = to_mesh_view(*arrays);
    auto result = std::make_unique<topotet_mesh>();
    result->cell_fields = read_cell_fields(*arrays);
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
    if (!data.cell_fields.empty() && result->mesh.tet_capacity() != data.tets.size())
      return fail(TOPOTET_INTERNAL_ERROR, std::string(path) + ": the build changed the tet count: the cell arrays do not fit");
    result->cell_fields = std::move(data.cell_fields);
    *mesh = result.release();
    return TOPOTET_OK;
  });
}

topotet_status topotet_mesh_write(const topotet_mesh* mesh, const char* path) {
  return guarded([&] {
    if (path == nullptr || mesh == nullptr) return fail(TOPOTET_INVALID_INPUT, "topotet_mesh_write: NULL argument");
    std::string message;
    topotet::MeshData data = mesh->mesh.to_mesh_data();
    if (!mesh->cell_fields.empty()) {
      if (data.tets.size() != mesh->mesh.tet_capacity())
        return fail(TOPOTET_INTERNAL_ERROR, "topotet_mesh_write: the mesh has dead tets: the cell arrays do not fit");
      data.cell_fields = mesh->cell_fields;
    }
    const Status s = topotet::try_write_mesh(path, data, message);
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
    data.cell_fields = mesh->cell_fields;  // the split tets take their pieces' share (isosurface.h)
    const topotet::IsoEmbedReport embedded = topotet::embed_isosurfaces(data, levels, embed);
    topotet::TetMesh rebuilt = topotet::build_tet_mesh(data);
    mesh->mesh = std::move(rebuilt);
    mesh->cell_fields = std::move(data.cell_fields);
    mesh->field_bound.clear();
    mesh->vertex_map.clear();
    mesh->has_substructures = false;
    for (std::size_t i = 0; i < embedded.levels.size(); ++i) {
      mesh->isosurfaces.push_back(embedded.levels[i]);
      if (refs_out != nullptr) refs_out[i] = embedded.levels[i].ref;
    }
    return TOPOTET_OK;
  });
}

namespace {

// The C options as the library's (without the mesh's isosurfaces); NULL = the defaults.
topotet_status to_simplify_options(const topotet_options* options, topotet::SimplifyOptions& o) {
  topotet_options c;
  topotet_options_init(&c);
  if (options != nullptr) c = *options;
  if (c.target_vertices < 0) return fail(TOPOTET_INVALID_INPUT, "target_vertices must be >= 0");
  if (c.engine != 0 && c.engine != 1) return fail(TOPOTET_INVALID_INPUT, "engine must be 0 (parallel) or 1 (sequential)");
  o.target_vertex_ratio = c.target_vertex_ratio;
  o.target_vertices = static_cast<std::uint64_t>(c.target_vertices);
  o.max_cost = c.max_cost;
  o.min_quality = c.min_quality;
  o.min_dihedral = c.min_dihedral;
  o.size_weight = c.size_weight;
  o.boundary_weight = c.boundary_weight;
  o.polyline_weight = c.polyline_weight;
  o.tolerance = c.tolerance;
  o.tolerance_rel = c.tolerance_rel;
  o.relax_tolerance = c.relax_tolerance != 0;
  o.relax_quality = c.relax_quality != 0;
  o.relax_features = c.relax_features != 0;
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
  o.track_field_bounds = c.track_field_bounds != 0;
  if (c.field_bound_mode < 0 || c.field_bound_mode > 1)
    return fail(TOPOTET_INVALID_INPUT, "field_bound_mode must be 0 (vertices) or 1 (everywhere)");
  o.field_bound_mode = static_cast<topotet::FieldBoundMode>(c.field_bound_mode);
  if (c.progress != nullptr) {
    const auto progress = c.progress;
    void* const user_data = c.progress_user_data;
    o.on_progress = [progress, user_data](double done) { return progress(done, user_data) != 0; };
  }
  return TOPOTET_OK;
}

// The library's counters into the C report (the fields every entry point fills the same way).
void fill_report(const topotet::Report& r, topotet_report* report) {
  report->status = to_c(r.status);
  report->field_bounds = r.field_bounds ? 1 : 0;
  report->field_bound_rel = r.field_bound_rel;
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
  report->tolerance_asked = r.tolerance_asked;
  report->min_quality_used = r.min_quality_used;
  report->min_dihedral_used = r.min_dihedral_used;
  report->relaxations = static_cast<std::int64_t>(r.relaxations.size());
  report->features_dropped = static_cast<std::int64_t>(r.features_dropped);
  report->stall_flips = static_cast<std::int64_t>(r.stall_flips);
  report->min_quality_lowest = r.min_quality_lowest;
  report->min_dihedral_lowest = r.min_dihedral_lowest;
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
    report->stop_beyond_reach = d.beyond_reach ? 1 : 0;
    std::snprintf(report->stop_dominant, sizeof report->stop_dominant, "%s", d.dominant);
    std::snprintf(report->stop_suggestion, sizeof report->stop_suggestion, "%s", d.suggestion.c_str());
  }
}

}  // namespace

topotet_status topotet_simplify(topotet_mesh* mesh, const topotet_options* options, topotet_report* report) {
  return guarded([&] {
    if (mesh == nullptr) return fail(TOPOTET_INVALID_INPUT, "topotet_simplify: mesh is NULL");
    topotet::SimplifyOptions o;
    if (const topotet_status converted = to_simplify_options(options, o); converted != TOPOTET_OK) return converted;
    o.isosurfaces = mesh->isosurfaces;
    // The cell arrays' original: the geometry before the collapses, with the arrays moved in (they
    // come back remapped, or as they were when the run changed nothing).
    std::unique_ptr<topotet::MeshData> original;
    if (!mesh->cell_fields.empty()) {
      original = std::make_unique<topotet::MeshData>(remap_geometry(mesh->mesh));
      original->cell_fields = std::move(mesh->cell_fields);
      mesh->cell_fields.clear();
    }
    mesh->has_substructures = false;
    const topotet::Report r = topotet::simplify(mesh->mesh, o, mesh->vertex_map);
    topotet::CellRemapReport remapped;
    std::string remap_error;
    topotet_status remap_status = TOPOTET_OK;
    if (original != nullptr && r.status == Status::kInvalidInput) {
      mesh->cell_fields = std::move(original->cell_fields);  // the mesh is untouched
    } else if (original != nullptr) {
      // Every other status may have changed the mesh: the arrays follow it, or are dropped.
      try {
        topotet::MeshData output = remap_geometry(mesh->mesh);
        topotet::run_with_thread_limit(o.num_threads, [&] { remapped = topotet::remap_cell_fields(*original, output); });
        mesh->cell_fields = std::move(output.cell_fields);
      } catch (const std::bad_alloc&) {
        remap_status = TOPOTET_OUT_OF_MEMORY;
        remap_error = "out of memory while remapping the cell arrays: they were dropped";
      } catch (const std::exception& e) {
        remap_status = TOPOTET_INTERNAL_ERROR;
        remap_error = std::string("internal error while remapping the cell arrays (they were dropped): ") + e.what();
      }
    }
    mesh->field_bound = r.field_bounds ? r.field_bound : std::vector<double>{};
    if (report != nullptr) {
      *report = topotet_report{};
      report->cell_overlap_pairs = static_cast<std::int64_t>(remapped.overlap_pairs);
      report->cell_nearest_new_tets = static_cast<std::int64_t>(remapped.nearest_new_tets);
      report->cell_nearest_original_tets = static_cast<std::int64_t>(remapped.nearest_original_tets);
      report->cell_covered_volume_fraction = remapped.covered_volume_fraction;
      report->cell_remap_seconds = remapped.seconds;
      fill_report(r, report);
    }
    const topotet_status s = to_c(r.status);
    if (s != TOPOTET_OK && s != TOPOTET_STOPPED_EARLY) return fail(s, r.message);
    if (remap_status != TOPOTET_OK) {
      if (report != nullptr) report->status = remap_status;
      return fail(remap_status, remap_error);
    }
    return s;
  });
}

void topotet_out_of_core_options_init(topotet_out_of_core_options* ooc) {
  if (ooc != nullptr) *ooc = topotet_out_of_core_options{};
}

topotet_status topotet_simplify_out_of_core(const char* input, const char* output, const topotet_options* options,
                                            const topotet_out_of_core_options* ooc, topotet_report* report,
                                            topotet_out_of_core_report* ooc_report) {
  return guarded([&] {
    if (input == nullptr || output == nullptr || ooc == nullptr)
      return fail(TOPOTET_INVALID_INPUT, "topotet_simplify_out_of_core: input, output and ooc must not be NULL");
    topotet::SimplifyOptions o;
    if (const topotet_status converted = to_simplify_options(options, o); converted != TOPOTET_OK) return converted;
    if (o.on_progress) return fail(TOPOTET_INVALID_INPUT, "topotet_simplify_out_of_core: no progress callback out of core (set it to NULL)");
    if (ooc->memory_limit_bytes < 0 || ooc->pieces < 0 || ooc->piece_tets < 0 || ooc->extensive_count < 0 ||
        ooc->categorical_count < 0)
      return fail(TOPOTET_INVALID_INPUT,
                  "topotet_simplify_out_of_core: memory_limit_bytes, pieces, piece_tets and the counts must be >= 0");
    topotet::OutOfCoreOptions c;
    c.memory_limit_bytes = static_cast<std::uint64_t>(ooc->memory_limit_bytes);
    c.pieces = static_cast<std::uint32_t>(ooc->pieces);
    c.piece_tets = static_cast<std::uint64_t>(ooc->piece_tets);
    if (ooc->scratch_parent != nullptr) c.scratch_parent = ooc->scratch_parent;
    if (ooc->vertex_map_path != nullptr) c.vertex_map_path = ooc->vertex_map_path;
    const auto names = [](int count, const char* const* list, std::vector<std::string>& into) {
      if (count > 0 && list == nullptr) throw ArgumentError{"topotet_simplify_out_of_core: a name list is NULL"};
      for (int i = 0; i < count; ++i) {
        if (list[i] == nullptr) throw ArgumentError{"topotet_simplify_out_of_core: a NULL cell array name"};
        into.emplace_back(list[i]);
      }
    };
    names(ooc->extensive_count, ooc->extensive_names, c.cell_remap.extensive);
    names(ooc->categorical_count, ooc->categorical_names, c.cell_remap.categorical);
    topotet::OutOfCoreReport r;
    topotet::run_with_thread_limit(o.num_threads, [&] { r = topotet::simplify_out_of_core(input, output, o, c); });
    if (report != nullptr) {
      *report = topotet_report{};
      fill_report(r.report, report);
    }
    if (ooc_report != nullptr) {
      ooc_report->pieces = static_cast<int>(r.pieces);
      ooc_report->pieces_left = static_cast<int>(r.output_pieces);
      ooc_report->levels = static_cast<int>(r.levels.size());
      ooc_report->piece_tet_limit = static_cast<std::int64_t>(r.piece_tet_limit);
      ooc_report->peak_rss_bytes = static_cast<std::int64_t>(r.peak_rss_bytes);
      ooc_report->scratch_peak_bytes = static_cast<std::int64_t>(r.scratch_peak_bytes);
      ooc_report->cut_seconds = r.cut_seconds;
      ooc_report->write_seconds = r.write_seconds;
    }
    return to_c(r.report.status);
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
int topotet_mesh_cell_field_count(const topotet_mesh* mesh) {
  return mesh != nullptr ? static_cast<int>(mesh->cell_fields.size()) : 0;
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

topotet_status topotet_mesh_cell_field_info(const topotet_mesh* mesh, int i, const char** name, int* components,
                                            topotet_cell_kind* kind) {
  if (mesh == nullptr || i < 0 || i >= static_cast<int>(mesh->cell_fields.size()))
    return fail(TOPOTET_INVALID_INPUT, "topotet_mesh_cell_field_info: no cell array " + std::to_string(i));
  const topotet::CellField& f = mesh->cell_fields[static_cast<std::size_t>(i)];
  if (name != nullptr) *name = f.name.c_str();
  if (components != nullptr) *components = f.components;
  if (kind != nullptr) *kind = static_cast<topotet_cell_kind>(f.kind);
  return TOPOTET_OK;
}

const double* topotet_mesh_cell_field_values(const topotet_mesh* mesh, int i) {
  if (mesh == nullptr || i < 0 || i >= static_cast<int>(mesh->cell_fields.size())) return nullptr;
  return mesh->cell_fields[static_cast<std::size_t>(i)].values.data();
}

topotet_status topotet_mesh_add_cell_field(topotet_mesh* mesh, const topotet_cell_field_view* field, int64_t row_count) {
  return guarded([&] {
    if (mesh == nullptr || field == nullptr) return fail(TOPOTET_INVALID_INPUT, "topotet_mesh_add_cell_field: NULL argument");
    if (row_count != static_cast<std::int64_t>(mesh->mesh.tet_capacity()))
      return fail(TOPOTET_INVALID_INPUT, "cell array '" + std::string(field->name != nullptr ? field->name : "") + "': " +
                                             std::to_string(row_count) + " rows for " +
                                             std::to_string(mesh->mesh.tet_capacity()) + " tets");
    topotet::CellField f = read_cell_field(*field, static_cast<int>(mesh->cell_fields.size()),
                                           static_cast<std::int64_t>(mesh->mesh.tet_capacity()), mesh->cell_fields);
    mesh->cell_fields.push_back(std::move(f));
    return TOPOTET_OK;
  });
}

topotet_status topotet_mesh_set_cell_field_kind(topotet_mesh* mesh, int i, topotet_cell_kind kind) {
  if (mesh == nullptr || i < 0 || i >= static_cast<int>(mesh->cell_fields.size()))
    return fail(TOPOTET_INVALID_INPUT, "topotet_mesh_set_cell_field_kind: no cell array " + std::to_string(i));
  topotet::CellField& f = mesh->cell_fields[static_cast<std::size_t>(i)];
  if (const int k = stored_value(kind); k < TOPOTET_CELL_INTENSIVE || k > TOPOTET_CELL_EXTENSIVE)
    return fail(TOPOTET_INVALID_INPUT, "cell array '" + f.name + "': unknown kind " + std::to_string(k) +
                                           " (0 intensive, 1 categorical, 2 extensive)");
  f.kind = static_cast<topotet::CellFieldKind>(kind);
  return TOPOTET_OK;
}

const double* topotet_mesh_field_bounds(const topotet_mesh* mesh) {
  return mesh != nullptr && !mesh->field_bound.empty() ? mesh->field_bound.data() : nullptr;
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

topotet_status topotet_mesh_copy_cell_field(const topotet_mesh* mesh, int i, topotet_out_view out) {
  if (mesh == nullptr) return fail(TOPOTET_INVALID_INPUT, "cell array: mesh is NULL");
  if (i < 0 || i >= static_cast<int>(mesh->cell_fields.size()))
    return fail(TOPOTET_INVALID_INPUT, "topotet_mesh_copy_cell_field: no cell array " + std::to_string(i));
  const topotet::CellField& f = mesh->cell_fields[static_cast<std::size_t>(i)];
  const std::string what = "cell array '" + f.name + "'";
  if (out.data == nullptr) return fail(TOPOTET_INVALID_INPUT, what + ": output array is NULL");
  if (type_size(out.type) == 0) return fail(TOPOTET_INVALID_INPUT, what + ": unknown output type");
  const int n = f.components;
  if (is_integer(out.type)) {  // labels: every value must be an integer of the output's range
    const double lo = out.type == TOPOTET_INT32 ? -2147483648.0 : -9223372036854775808.0;
    for (std::size_t k = 0; k < f.values.size(); ++k)
      if (f.values[k] != std::trunc(f.values[k]) || f.values[k] < lo || f.values[k] >= -lo)
        return fail(TOPOTET_INVALID_INPUT, what + ": value " + std::to_string(f.values[k]) + " of tet " +
                                               std::to_string(k / static_cast<std::size_t>(n) + 1) +
                                               " is not an integer of the output type");
  }
  for (std::size_t t = 0; t < f.values.size() / static_cast<std::size_t>(n); ++t)
    for (int c = 0; c < n; ++c) {
      const double x = f.values[t * static_cast<std::size_t>(n) + static_cast<std::size_t>(c)];
      if (is_integer(out.type))
        write_int(out, static_cast<std::int64_t>(t), c, n, static_cast<std::int64_t>(x));
      else
        write_real(out, static_cast<std::int64_t>(t), c, n, x);
    }
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
