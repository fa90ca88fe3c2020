#include "cell_data/tet_overlap.h"

#include <array>
#include <cmath>

#include <glm/geometric.hpp>

namespace topotet::cell_data {
namespace {

constexpr int kFace[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};

// Is every corner of `other` strictly outside a face plane of t (a separating plane)?
bool separated_by_a_face_of(const Tet& t, const glm::dvec3 (&other)[4]) {
  for (int f = 0; f < 4; ++f) {
    const glm::dvec3& p0 = t[kFace[f][0]];
    const glm::dvec3 n = glm::cross(t[kFace[f][1]] - p0, t[kFace[f][2]] - p0);
    const double inner = glm::dot(n, t[f] - p0);  // the side of the opposite corner
    if (inner == 0.0) continue;                   // a flat t: no plane to trust
    bool all_out = true;
    for (int k = 0; k < 4 && all_out; ++k) all_out = glm::dot(n, other[k] - p0) * inner < 0.0;
    if (all_out) return true;
  }
  return false;
}

using Plane = TetClipper::Plane;

struct Piece {
  glm::dvec3 v[4];
};

// The pieces of one clip: at most 81 after four planes (each tet gives at most 3).
class Pieces {
 public:
  static constexpr int kMax = 81;
  void push(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& d) {
    items_[count_++] = {{a, b, c, d}};
  }
  // A prism with triangles (a0, a1, a2) and (b0, b1, b2), bi joined to ai by planar side faces.
  void push_prism(const glm::dvec3& a0, const glm::dvec3& a1, const glm::dvec3& a2, const glm::dvec3& b0,
                  const glm::dvec3& b1, const glm::dvec3& b2) {
    push(a0, a1, a2, b0);
    push(a1, a2, b0, b1);
    push(a2, b0, b1, b2);
  }
  int size() const { return count_; }
  const Piece& operator[](int i) const { return items_[static_cast<std::size_t>(i)]; }
  void clear() { count_ = 0; }

 private:
  std::array<Piece, kMax> items_;
  int count_ = 0;
};

// The part of `t` inside `plane`, appended to `out` as tets.
void clip(const Piece& t, const Plane& plane, Pieces& out) {
  double d[4];
  int inside[4], outside[4], ni = 0, no = 0;
  for (int k = 0; k < 4; ++k) {
    d[k] = plane.distance(t.v[k]);
    if (d[k] <= 0) {
      inside[ni++] = k;
    } else {
      outside[no++] = k;
    }
  }
  // Where edge (i inside, o outside) crosses the plane; d[i] <= 0 < d[o], so no division by 0.
  const auto cut = [&](int i, int o) { return t.v[i] + (t.v[o] - t.v[i]) * (d[i] / (d[i] - d[o])); };
  switch (ni) {
    case 4:
      out.push(t.v[0], t.v[1], t.v[2], t.v[3]);
      return;
    case 0:
      return;
    case 1: {
      const int i = inside[0];
      out.push(t.v[i], cut(i, outside[0]), cut(i, outside[1]), cut(i, outside[2]));
      return;
    }
    case 3: {  // the tet minus the corner at the outside vertex: triangle inside -> triangle on the plane
      const int o = outside[0];
      const int a = inside[0], b = inside[1], c = inside[2];
      out.push_prism(t.v[a], t.v[b], t.v[c], cut(a, o), cut(b, o), cut(c, o));
      return;
    }
    default: {  // two inside (a, b), two outside (c, e): a wedge with triangles at a and at b
      const int a = inside[0], b = inside[1], c = outside[0], e = outside[1];
      out.push_prism(t.v[a], cut(a, c), cut(a, e), t.v[b], cut(b, c), cut(b, e));
      return;
    }
  }
}

}  // namespace

double tet_volume(const glm::dvec3& a, const glm::dvec3& b, const glm::dvec3& c, const glm::dvec3& d) {
  return std::abs(glm::dot(b - a, glm::cross(c - a, d - a))) / 6.0;
}

// The planes are oriented by the vertex opposite each face, so that B's orientation does not
// matter; a vertex on its face's plane means B is flat.
TetClipper::TetClipper(const Tet& b) {
  for (int k = 0; k < 4; ++k) corners_[k] = b[k];
  for (int f = 0; f < 4; ++f) {
    const glm::dvec3& p0 = b[kFace[f][0]];
    glm::dvec3 n = glm::cross(b[kFace[f][1]] - p0, b[kFace[f][2]] - p0);
    double offset = glm::dot(n, p0);
    if (glm::dot(n, b[f]) - offset > 0) {
      n = -n;
      offset = -offset;
    }
    if (!(glm::dot(n, b[f]) - offset < 0)) flat_ = true;
    planes_[f] = {n, offset};
  }
}

double TetClipper::overlap_volume(const Tet& a) const {
  if (flat_) return 0.0;
  const Plane* planes = planes_;
  // Only the planes that cut A need clipping: A is on the inner side of the others, and so is
  // every piece of A (usually A straddles one or two of B's faces).
  bool cuts[4];
  bool any_cut = false;
  for (int f = 0; f < 4; ++f) {
    int out = 0;
    for (int k = 0; k < 4; ++k) {
      if (planes[f].distance(a[k]) > 0) ++out;
    }
    if (out == 4) return 0.0;  // a separating plane
    cuts[f] = out > 0;
    any_cut = any_cut || cuts[f];
  }
  if (!any_cut) return tet_volume(a[0], a[1], a[2], a[3]);
  if (separated_by_a_face_of(a, corners_)) return 0.0;

  Pieces buffers[2];
  buffers[0].push(a[0], a[1], a[2], a[3]);
  int from = 0;
  for (int f = 0; f < 4; ++f) {
    if (!cuts[f]) continue;
    const Plane& p = planes[f];
    Pieces& next = buffers[1 - from];
    next.clear();
    for (int i = 0; i < buffers[from].size(); ++i) clip(buffers[from][i], p, next);
    from = 1 - from;
    if (buffers[from].size() == 0) return 0.0;
  }
  double volume = 0.0;
  for (int i = 0; i < buffers[from].size(); ++i) {
    const Piece& t = buffers[from][i];
    volume += tet_volume(t.v[0], t.v[1], t.v[2], t.v[3]);
  }
  return volume;
}

}  // namespace topotet::cell_data
