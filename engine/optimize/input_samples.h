// The input's field where the output's field error is measured: at every input vertex
// (metrics/field_error, "original_to_simplified"). The optimisation after the collapses changes
// the interpolated field between the vertices (a flip retriangulates, a move shifts a vertex and
// its values), and a collapse's survivor has overwritten its own input position and values, so
// the input's vertices are recorded before the collapses. A flip or a move is then accepted only
// if the squared errors at the recorded vertices inside its region do not grow (swap.h, smooth.h):
// measured on LOX at 30% of the vertices, the flips and moves tripled the field RMS under a
// pointwise bound alone (docs/performance.md, "Quality after the collapses").
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include <glm/common.hpp>
#include <glm/mat3x3.hpp>
#include <glm/vec3.hpp>

#include "mesh/mesh_model.h"

namespace topotet {

// A tet of a region with its corners' positions and field values (the mesh's stride): the region
// before or after a flip or a move, which the mesh does not hold yet.
struct FieldTet {
  std::array<glm::dvec3, 4> p;
  std::array<const double*, 4> f;
};

// Locates points in a region given as tets: the tet that holds x is the first one whose smallest
// barycentric coordinate is >= 0, else the one where it is largest (x outside the region, or on
// a face up to rounding, where neighbours agree on the field). Each tet's barycentric map is
// inverted once, for the many points a region is asked about, and only the tets whose box holds
// x are tried (all of them when none does).
class RegionLocator {
 public:
  void reset(std::span<const FieldTet> tets);
  // The smallest barycentric coordinate of x in the tet found (>= 0 up to rounding when x lies in
  // the region); `tet` and `l` receive that tet's index and coordinates.
  double locate(const glm::dvec3& x, std::size_t& tet, std::array<double, 4>& l) const;
  // The same for a point that only matters when it lies in the region: -infinity, at once, when no
  // tet's box holds it (its smallest barycentric coordinate is then below -1e-9 in every tet).
  // Most points a region is asked about lie outside it, where locate() would try every tet again.
  double locate_if_inside(const glm::dvec3& x, std::size_t& tet, std::array<double, 4>& l) const {
    tet = 0;
    return search(x, true, tet, l);
  }

 private:
  struct Map {
    glm::dvec3 origin;
    glm::dmat3 inverse;  // x - origin -> the coordinates of corners 1..3
    glm::dvec3 lo, hi;   // the tet's box, grown by a hair: a point with a barycentric coordinate
                         // above -1e-9 of the tet is in it
    bool valid;          // positive volume
  };
  double search(const glm::dvec3& x, bool boxes, std::size_t& tet, std::array<double, 4>& l) const;
  std::vector<Map> maps_;
};

// Tet tv of the mesh as it stands, with its corners' field values (stride k).
inline FieldTet field_tet(const MeshModel& mesh, const std::array<VertId, 4>& tv, int k) {
  FieldTet t;
  for (std::size_t j = 0; j < 4; ++j) {
    t.p[j] = mesh.positions[tv[j]];
    t.f[j] = mesh.field_values.data() + static_cast<std::size_t>(tv[j]) * static_cast<std::size_t>(k);
  }
  return t;
}

// Component c of the linear field of t at barycentric coordinates l.
inline double interpolate(const FieldTet& t, const std::array<double, 4>& l, int c) {
  return l[0] * t.f[0][c] + l[1] * t.f[1][c] + l[2] * t.f[2][c] + l[3] * t.f[3][c];
}

class InputSamples {
 public:
  // Records every vertex's position and field values (call before the first collapse): only the
  // ones a collapse or a move will overwrite are read back from here (a vertex is reshaped then:
  // mesh_model.h), the others from the mesh itself, whose dead vertices keep their entries. In
  // single precision, relative to the bounding box and to each component's minimum, so within
  // 1e-7 of the diagonal and of the range: (12 + 4 x components) bytes per vertex. Nothing is
  // recorded for a mesh without fields.
  explicit InputSamples(const MeshModel& mesh);

  // The grid over the recorded vertices (about two a cell), built once the collapses are done
  // (call before inside()): it does not weigh on the collapses' peak memory.
  void index(const MeshModel& mesh);

  // The recorded vertices inside the region `before`, for errors_after() to compare with: the
  // squared field errors there of the linear field of `before` (in units of each component's range
  // over the input's vertices, summed over the components). A vertex of the mesh that is live,
  // still at its input place with its input values (not reshaped) and not `moving` (the vertex a
  // smoothing move shifts; kInvalid for a flip) is left out: every field of the region takes its
  // own value there. Deterministic: samples in increasing cell then vertex order.
  struct Inside {
    std::vector<VertId> vertices;
    std::vector<glm::dvec3> places;  // their input positions
    double error = 0.0;              // the sum over them, of the field of `before`
  };
  void inside(const MeshModel& mesh, std::span<const FieldTet> before, VertId moving, Inside& out) const;

  // The same sum for the linear field of `after`: the region of inside() retriangulated, or with
  // its vertex `moving` moved (the same point set).
  double errors_after(const MeshModel& mesh, std::span<const FieldTet> after, const Inside& in) const;

  bool empty() const { return stride_ == 0 || values_.empty(); }
  int stride() const { return stride_; }
  std::size_t memory_bytes() const;

 private:
  glm::ivec3 cell_of(const glm::dvec3& p) const;
  std::size_t index(int x, int y, int z) const {
    return (static_cast<std::size_t>(z) * static_cast<std::size_t>(dims_.y) + static_cast<std::size_t>(y)) *
               static_cast<std::size_t>(dims_.x) +
           static_cast<std::size_t>(x);
  }
  // Vertex s's input position and component m's input value: the mesh's own entries unless a
  // collapse or a move overwrote them.
  glm::dvec3 input_position(const MeshModel& mesh, VertId s) const;
  double input_value(const MeshModel& mesh, VertId s, std::size_t m) const;
  double squared_error(const MeshModel& mesh, const FieldTet& t, const std::array<double, 4>& l, VertId s) const;

  int stride_ = 0;
  glm::dvec3 box_lo_{0.0};
  std::vector<glm::vec3> positions_;  // [vertex] input position - box_lo_
  std::vector<double> value_lo_;      // [component] its smallest input value
  std::vector<float> values_;         // [vertex * stride + component] input value - value_lo_
  std::vector<double> inv_range_;     // [component] 1 / its range (0 for a constant one)
  glm::dvec3 origin_{0.0}, inv_cell_{0.0};
  glm::ivec3 dims_{1, 1, 1};
  std::vector<std::uint32_t> start_;  // [cell] first entry of ids_; one past the last cell at the end
  std::vector<VertId> ids_;           // the recorded vertices, cell by cell, increasing ids within a cell
};

}  // namespace topotet
