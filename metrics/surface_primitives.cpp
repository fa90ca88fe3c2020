// special_primitives: every tet face and listed triangle is bucketed by its smallest vertex
// (counting sort), each bucket is sorted by the other two vertices (and the owner), and each run of equal faces
// is classified by the tets and listed triangles in it. Linear in the mesh size, and the buckets
// are independent, so they are sorted and classified in parallel; the output order (sorted vertex
// triples) does not depend on the thread count.
#include "surface_primitives.h"

#include <algorithm>
#include <atomic>
#include <string>

#include "parallel/for_range.h"
#include "topotet/error.h"
#include "topotet/metrics/surface_distance.h"

namespace topotet::metrics::detail {
namespace {

// A face in the bucket of its smallest vertex: the other two, and where it came from.
struct BucketedFace {
  VertId b, c;
  std::uint32_t owner;  // tet id, or tet count + listed triangle id
  bool operator<(const BucketedFace& o) const {
    return b != o.b ? b < o.b : c != o.c ? c < o.c : owner < o.owner;
  }
};

std::array<VertId, 3> sorted3(VertId x, VertId y, VertId z) {
  if (x > y) std::swap(x, y);
  if (y > z) std::swap(y, z);
  if (x > y) std::swap(x, y);
  return {x, y, z};
}

// Buckets of vertices handled by one task when classifying: enough work to amortise a task.
constexpr std::size_t kBucketsPerChunk = 4096;

}  // namespace

SurfacePrimitives special_primitives(const MeshData& m, const char* which) {
  const std::size_t nv = m.vertex_count(), nt = m.tet_count();
  auto out_of_range = [&] {
    throw InputError(std::string("surface_distance: ") + which + ": vertex index out of range");
  };
  for (const auto& tet : m.tets)
    for (VertId x : tet)
      if (x >= nv) out_of_range();
  for (const Triangle& t : m.triangles)
    for (VertId x : t.v)
      if (x >= nv) out_of_range();
  for (const Segment& s : m.segments)
    if (s.v[0] >= nv || s.v[1] >= nv) out_of_range();

  // Counting sort by smallest vertex: bucket a holds [start[a], start[a + 1]).
  auto face_of = [&](std::size_t slot) {
    if (slot < 4 * nt) {
      const auto& t = m.tets[slot / 4];
      const int f = static_cast<int>(slot % 4);  // the face opposite local vertex f
      return sorted3(t[(f + 1) % 4], t[(f + 2) % 4], t[(f + 3) % 4]);
    }
    const auto& v = m.triangles[slot - 4 * nt].v;
    return sorted3(v[0], v[1], v[2]);
  };
  const std::size_t slot_count = 4 * nt + m.triangles.size();
  // Counts and scatter in parallel (atomic counters): the order inside a bucket then depends on
  // the threads, but every bucket is sorted by (b, c, owner) below, so the result does not.
  constexpr std::size_t kSlotGrain = 16384;
  std::vector<std::uint32_t> start(nv + 1, 0);
  parallel::for_range<std::size_t>(0, slot_count, kSlotGrain, "surface_face_count", [&](std::size_t b, std::size_t e) {
    for (std::size_t slot = b; slot < e; ++slot)
      std::atomic_ref(start[face_of(slot)[0] + 1]).fetch_add(1, std::memory_order_relaxed);
  });
  for (std::size_t a = 0; a < nv; ++a) start[a + 1] += start[a];
  std::vector<BucketedFace> faces(slot_count);
  {
    std::vector<std::uint32_t> cursor(start.begin(), start.end() - 1);
    parallel::for_range<std::size_t>(0, slot_count, kSlotGrain, "surface_face_scatter", [&](std::size_t b, std::size_t e) {
      for (std::size_t slot = b; slot < e; ++slot) {
        const auto k = face_of(slot);
        const auto owner = static_cast<std::uint32_t>(slot < 4 * nt ? slot / 4 : nt + (slot - 4 * nt));
        faces[std::atomic_ref(cursor[k[0]]).fetch_add(1, std::memory_order_relaxed)] = {k[1], k[2], owner};
      }
    });
  }

  const auto material = [&](std::size_t t) { return m.tet_material.empty() ? 0 : m.tet_material[t]; };
  const std::size_t chunks = (nv + kBucketsPerChunk - 1) / kBucketsPerChunk;
  std::vector<SurfacePrimitives> parts(chunks);
  parallel::for_range<std::size_t>(0, chunks, 1, "surface_faces", [&](std::size_t c0, std::size_t c1) {
    for (std::size_t chunk = c0; chunk < c1; ++chunk) {
      SurfacePrimitives& part = parts[chunk];
      const std::size_t a_end = std::min(nv, (chunk + 1) * kBucketsPerChunk);
      for (std::size_t a = chunk * kBucketsPerChunk; a < a_end; ++a) {
        const auto first = faces.begin() + start[a], last = faces.begin() + start[a + 1];
        std::sort(first, last);
        for (auto i = first; i != last;) {
          auto j = i + 1;
          while (j != last && j->b == i->b && j->c == i->c) ++j;
          std::int32_t ref = kSurfaceUnlistedRef;
          bool listed = false;
          std::int32_t mats[2] = {0, 0};
          std::size_t mat_count = 0;
          for (auto k = i; k != j; ++k) {
            if (k->owner >= nt) {
              const std::int32_t r = m.triangles[k->owner - nt].ref;
              ref = listed ? std::max(ref, r) : r;  // the largest of several listed refs
              listed = true;
            } else {
              if (mat_count < 2) mats[mat_count] = material(k->owner);
              ++mat_count;
            }
          }
          SurfaceLabel label{};
          bool special = listed;
          if (mat_count == 0) {
            label = {ref, kSurfaceNoMaterial, kSurfaceNoMaterial};
          } else if (mat_count == 1) {
            label = {ref, kSurfaceOutside, mats[0]};  // kSurfaceOutside is the smallest int32
            special = true;
          } else {
            label = {ref, std::min(mats[0], mats[1]), std::max(mats[0], mats[1])};
            special = special || mats[0] != mats[1];
          }
          if (special) {
            part.triangles.push_back({static_cast<VertId>(a), i->b, i->c});
            part.triangle_label.push_back(label);
          }
          i = j;
        }
      }
    }
  });
  SurfacePrimitives out;
  for (const SurfacePrimitives& part : parts) {
    out.triangles.insert(out.triangles.end(), part.triangles.begin(), part.triangles.end());
    out.triangle_label.insert(out.triangle_label.end(), part.triangle_label.begin(), part.triangle_label.end());
  }

  std::vector<std::pair<std::array<VertId, 2>, std::int32_t>> segments;
  segments.reserve(m.segments.size());
  for (const Segment& s : m.segments) segments.push_back({{std::min(s.v[0], s.v[1]), std::max(s.v[0], s.v[1])}, s.ref});
  std::sort(segments.begin(), segments.end());
  segments.erase(std::unique(segments.begin(), segments.end()), segments.end());
  for (const auto& [v, ref] : segments) {
    out.segments.push_back(v);
    out.segment_label.push_back({ref, kPolylineMarker, 0});
  }
  return out;
}

}  // namespace topotet::metrics::detail
