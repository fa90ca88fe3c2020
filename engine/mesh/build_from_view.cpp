// build_mesh_model from a caller's strided arrays: loads them into the model's own arrays (the only
// copy), then hands over to the one validation path, detail::build_loaded_model (build_mesh.cpp).
#include <cstring>
#include <string>

#include "mesh/mesh_view.h"
#include "topotet/error.h"

namespace topotet {
namespace {

std::size_t type_size(StridedArray::Type t) {
  return t == StridedArray::Type::kFloat32 || t == StridedArray::Type::kInt32 ? 4 : 8;
}

const char* address(const StridedArray& a, std::size_t row, int col, int width) {
  const auto size = static_cast<std::int64_t>(type_size(a.type));
  const std::int64_t column = a.column_stride != 0 ? a.column_stride : size;
  const std::int64_t stride = a.row_stride != 0 ? a.row_stride : width * column;
  return static_cast<const char*>(a.data) + static_cast<std::int64_t>(row) * stride + col * column;
}

template <class T>
T load(const char* p) {
  T x;
  std::memcpy(&x, p, sizeof x);  // the caller's rows need not be aligned
  return x;
}

void check_type(const StridedArray& a, bool integer, const char* what) {
  if (a.is_integer() != integer)
    throw InputError(std::string(what) + (integer ? ": must hold integers" : ": must hold reals"));
}

std::int32_t label(const StridedArray& a, std::size_t row, const char* what) {
  const std::int64_t x = a.integer(row, 0, 1);
  if (x < INT32_MIN || x > INT32_MAX)
    throw InputError(std::string(what) + " " + std::to_string(row + 1) + ": " + std::to_string(x) +
                     " does not fit in 32 bits");
  return static_cast<std::int32_t>(x);
}

}  // namespace

double StridedArray::real(std::size_t row, int col, int width) const {
  const char* p = address(*this, row, col, width);
  return type == Type::kFloat32 ? load<float>(p) : load<double>(p);
}

std::int64_t StridedArray::integer(std::size_t row, int col, int width) const {
  const char* p = address(*this, row, col, width);
  return type == Type::kInt32 ? load<std::int32_t>(p) : load<std::int64_t>(p);
}

MeshModel build_mesh_model(const MeshView& view, const BuildOptions& options, BuildNotes* notes) {
  const std::size_t nv = view.vertex_count, nt = view.tet_count;
  // The same size checks, with the same messages, as for a MeshData (build_mesh.cpp, check_sizes).
  if (nv >= kInvalid) throw InputError("too many vertices for 32-bit ids: " + std::to_string(nv));
  if (nt >= kInvalid / 4) throw InputError("too many tets for 32-bit ids: " + std::to_string(nt));
  if (nt == 0) throw InputError("the mesh has no tetrahedra");
  if (view.index_base != 0 && view.index_base != 1) throw InputError("index_base must be 0 or 1");
  if (nv > 0 && !view.positions.given()) throw InputError("positions not given");
  if (!view.tets.given()) throw InputError("tets not given");
  check_type(view.positions, false, "positions");
  check_type(view.tets, true, "tets");
  if (view.materials.given()) check_type(view.materials, true, "materials");
  if (view.vertex_refs.given()) check_type(view.vertex_refs, true, "vertex_refs");

  MeshModel m;
  m.positions.resize(nv);
  for (std::size_t v = 0; v < nv; ++v)
    m.positions[v] = {view.positions.real(v, 0, 3), view.positions.real(v, 1, 3), view.positions.real(v, 2, 3)};
  m.tets.resize(nt);
  for (std::size_t t = 0; t < nt; ++t)
    for (int k = 0; k < 4; ++k) {
      // Indices that are vertex ids once rebased are stored as they are: out of range or repeated,
      // the common checks name them. Only those that fit no id at all are refused here.
      const std::int64_t x = view.tets.integer(t, k, 4) - view.index_base;
      if (x < 0 || x >= static_cast<std::int64_t>(kInvalid))
        throw InputError("tet " + std::to_string(t + 1) + ": vertex index " + std::to_string(x + view.index_base) +
                         " out of range (index_base " + std::to_string(view.index_base) + ")");
      m.tets[t][k] = static_cast<VertId>(x);
    }
  m.material.assign(nt, 0);
  if (view.materials.given())
    for (std::size_t t = 0; t < nt; ++t) m.material[t] = label(view.materials, t, "material");
  m.vertex_refs.assign(nv, 0);
  if (view.vertex_refs.given())
    for (std::size_t v = 0; v < nv; ++v) m.vertex_refs[v] = label(view.vertex_refs, v, "vertex ref");

  int stride = 0;
  for (const FieldView& f : view.fields) {
    if (f.components < 1) throw InputError("field '" + f.name + "': " + std::to_string(f.components) + " components");
    if (nv > 0 && !f.values.given()) throw InputError("field '" + f.name + "': values not given");
    check_type(f.values, false, ("field '" + f.name + "'").c_str());
    m.fields.push_back({f.name, f.components});
    stride += f.components;
  }
  m.field_values.assign(nv * static_cast<std::size_t>(stride), 0.0);
  int offset = 0;
  for (const FieldView& f : view.fields) {
    for (std::size_t v = 0; v < nv; ++v)
      for (int c = 0; c < f.components; ++c)
        m.field_values[v * stride + offset + c] = f.values.real(v, c, f.components);
    offset += f.components;
  }
  static const std::vector<std::uint32_t> kNoRidges;
  static const std::vector<VertId> kNoRequired;
  return detail::build_loaded_model(std::move(m), {view.triangles, view.segments, kNoRidges, view.corners, kNoRequired},
                                    options, notes);
}

}  // namespace topotet
