// Nearly flat patches of the original surfaces (see flat_patches.h).
#include "guarantees/flat_patches.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <glm/geometric.hpp>

#include "guarantees/surface_tolerance.h"

namespace topotet {

namespace {

// cos 60 degrees: a patch triangle's normal stays within 60 degrees of the patch normal, far from
// the 90 degrees where the projection would fold it.
constexpr double kMinNormalCosine = 0.5;

struct EdgeUse {
  VertId lo, hi;
  std::uint32_t label, tri;
  bool forward;  // the triangle runs lo -> hi
  bool operator<(const EdgeUse& o) const {
    if (lo != o.lo) return lo < o.lo;
    if (hi != o.hi) return hi < o.hi;
    if (label != o.label) return label < o.label;
    return tri < o.tri;
  }
};

struct Neighbour {
  std::uint32_t tri = kInvalid;  // across this edge, the only other triangle of the label
  bool same_orientation = false;  // the two run the edge in opposite directions
};

}  // namespace

FlatPatches find_flat_patches(const SurfaceSoup& soup, double max_deviation) {
  const std::size_t n = soup.triangles.size();
  const auto& P = soup.positions;
  std::vector<EdgeUse> uses;
  uses.reserve(3 * n);
  for (std::uint32_t t = 0; t < n; ++t)
    for (int k = 0; k < 3; ++k) {
      const VertId a = soup.triangles[t][k], b = soup.triangles[t][(k + 1) % 3];
      uses.push_back({std::min(a, b), std::max(a, b), soup.triangle_label[t], t, a < b});
    }
  std::sort(uses.begin(), uses.end());
  // neighbours[3 t + k]: across edge k (from corner k to k + 1) of t.
  std::vector<Neighbour> neighbours(3 * n);
  auto edge_slot = [&](std::uint32_t t, VertId lo, VertId hi) {
    for (int k = 0; k < 3; ++k) {
      const VertId a = soup.triangles[t][k], b = soup.triangles[t][(k + 1) % 3];
      if (std::min(a, b) == lo && std::max(a, b) == hi) return 3 * std::size_t{t} + k;
    }
    return std::size_t{0};  // unreachable: the use came from this triangle
  };
  for (std::size_t i = 0; i < uses.size();) {
    std::size_t j = i + 1;
    while (j < uses.size() && uses[j].lo == uses[i].lo && uses[j].hi == uses[i].hi && uses[j].label == uses[i].label) ++j;
    if (j - i == 2) {  // manifold edge of its label: the patch may grow across it
      const EdgeUse& x = uses[i];
      const EdgeUse& y = uses[i + 1];
      const bool same = x.forward != y.forward;
      neighbours[edge_slot(x.tri, x.lo, x.hi)] = {y.tri, same};
      neighbours[edge_slot(y.tri, y.lo, y.hi)] = {x.tri, same};
    }
    i = j;
  }

  auto raw_normal = [&](std::uint32_t t) {
    const auto& v = soup.triangles[t];
    return glm::cross(P[v[1]] - P[v[0]], P[v[2]] - P[v[0]]);
  };

  FlatPatches out;
  out.patch_of.assign(n, kInvalid);
  std::vector<std::uint8_t> flipped(n, 0);
  std::vector<std::uint32_t> queue, members;
  // Seeds in the order of their centroids, not of their ids: the patches (and so every decision
  // of the tolerance check) must not depend on how the mesh is numbered.
  std::vector<std::uint32_t> seeds(n);
  std::vector<glm::dvec3> centroid(n);
  for (std::uint32_t t = 0; t < n; ++t) {
    seeds[t] = t;
    const auto& v = soup.triangles[t];
    centroid[t] = (P[v[0]] + P[v[1]] + P[v[2]]) / 3.0;
  }
  std::sort(seeds.begin(), seeds.end(), [&](std::uint32_t a, std::uint32_t b) {
    const glm::dvec3 &x = centroid[a], &y = centroid[b];
    if (x.x != y.x) return x.x < y.x;
    if (x.y != y.y) return x.y < y.y;
    if (x.z != y.z) return x.z < y.z;
    return a < b;
  });
  for (const std::uint32_t seed : seeds) {
    if (out.patch_of[seed] != kInvalid) continue;
    const auto id = static_cast<std::uint32_t>(out.patches.size());
    const glm::dvec3 raw = raw_normal(seed);
    const double len = glm::length(raw);
    out.patch_of[seed] = id;
    if (!(len > 0.0) || !std::isfinite(len)) {  // degenerate: a patch of its own that proves nothing
      out.patches.push_back({glm::dvec3(0.0, 0.0, 1.0), 0.0, std::numeric_limits<double>::infinity()});
      continue;
    }
    const glm::dvec3 normal = raw / len;
    const double offset = glm::dot(normal, P[soup.triangles[seed][0]]);
    auto within_slab = [&](std::uint32_t t) {
      for (VertId x : soup.triangles[t])
        if (std::abs(glm::dot(normal, P[x]) - offset) > max_deviation) return false;
      return true;
    };
    if (!within_slab(seed)) {  // cannot happen for a non-degenerate seed; kept for rounding
      out.patches.push_back({normal, offset, std::numeric_limits<double>::infinity()});
      continue;
    }
    queue.assign(1, seed);
    members.assign(1, seed);
    flipped[seed] = 0;
    for (std::size_t head = 0; head < queue.size(); ++head) {
      const std::uint32_t t = queue[head];
      for (int k = 0; k < 3; ++k) {
        const Neighbour nb = neighbours[3 * std::size_t{t} + k];
        if (nb.tri == kInvalid || out.patch_of[nb.tri] != kInvalid) continue;
        const bool flip = (flipped[t] != 0) != !nb.same_orientation;
        const glm::dvec3 r = raw_normal(nb.tri);
        const double rl = glm::length(r);
        if (!(rl > 0.0)) continue;
        if ((flip ? -1.0 : 1.0) * glm::dot(r, normal) < kMinNormalCosine * rl) continue;
        if (!within_slab(nb.tri)) continue;
        out.patch_of[nb.tri] = id;
        flipped[nb.tri] = flip ? 1 : 0;
        queue.push_back(nb.tri);
        members.push_back(nb.tri);
      }
    }
    double deviation = 0.0;
    for (std::uint32_t t : members)
      for (VertId x : soup.triangles[t]) deviation = std::max(deviation, std::abs(glm::dot(normal, P[x]) - offset));
    out.patches.push_back({normal, offset, deviation});
  }
  out.neighbour.resize(3 * n);
  for (std::size_t i = 0; i < 3 * n; ++i) out.neighbour[i] = neighbours[i].tri;
  // Boundary edges: an edge of a patch triangle whose other side is not the same patch (another
  // patch, no triangle, a non-manifold edge or a border of the label).
  for (std::uint32_t t = 0; t < n; ++t)
    for (int k = 0; k < 3; ++k) {
      const Neighbour nb = neighbours[3 * std::size_t{t} + k];
      if (nb.tri != kInvalid && out.patch_of[nb.tri] == out.patch_of[t]) continue;
      const VertId a = soup.triangles[t][k], b = soup.triangles[t][(k + 1) % 3];
      out.boundary.push_back({std::min(a, b), std::max(a, b)});
      out.boundary_patch.push_back(out.patch_of[t]);
    }
  return out;
}

}  // namespace topotet
