// The special faces of a mesh (see special_faces.h).
#include "mesh/special_faces.h"

#include <algorithm>

#include "parallel/for_range.h"

namespace topotet {

SpecialFaces find_special_faces(const detail::MeshModel& mesh) {
  // Finding each face's other tet by a scan of a star cost ~80 ns per face; matched at the smallest
  // vertex, the faces are few and sorted in cache. Blocks of vertices in parallel, then sorted by
  // (tet, local face), so the result does not depend on the schedule.
  constexpr std::size_t kBlock = 4096;
  const std::size_t nv = mesh.vertex_capacity();
  const std::size_t blocks = (nv + kBlock - 1) / kBlock;
  std::vector<std::vector<SpecialFace>> block_faces(blocks);
  struct FaceAt {  // a face of St(a) whose smallest vertex is a, keyed by its other two
    std::uint64_t key;
    TetId tet;
    std::uint8_t local;
    bool operator<(const FaceAt& o) const { return key != o.key ? key < o.key : tet < o.tet; }
  };
  parallel::for_range<std::size_t>(0, blocks, 1, "special_faces", [&](std::size_t b0, std::size_t b1) {
    std::vector<FaceAt> at;
    for (std::size_t b = b0; b < b1; ++b) {
      for (std::size_t vi = b * kBlock; vi < std::min(nv, (b + 1) * kBlock); ++vi) {
        const VertId a = static_cast<VertId>(vi);
        if (mesh.is_dead_vertex(a)) continue;
        at.clear();
        mesh.for_each_tet_of(a, [&](TetId t) {
          const auto& tv = mesh.tets[t];
          for (int f = 0; f < 4; ++f) {
            if (tv[f] == a) continue;  // face f is opposite local vertex f: it has a otherwise
            VertId x = kInvalid, y = kInvalid;
            for (int k = 0; k < 4; ++k) {
              if (k == f || tv[k] == a) continue;
              (x == kInvalid ? x : y) = tv[k];
            }
            if (x < a || y < a) continue;  // matched at its smallest vertex
            at.push_back({(std::uint64_t{std::min(x, y)} << 32) | std::max(x, y), t, static_cast<std::uint8_t>(f)});
          }
        });
        std::sort(at.begin(), at.end());
        for (std::size_t i = 0; i < at.size();) {
          const bool pair = i + 1 < at.size() && at[i + 1].key == at[i].key;
          const SpecialFace face{at[i].tet, at[i].local, pair ? at[i + 1].local : std::uint8_t{0},
                                 pair ? at[i + 1].tet : kInvalid};
          i += pair ? 2 : 1;
          const bool special = face.other == kInvalid || is_surface_face(mesh.flags[face.tet], face.local) ||
                               is_surface_face(mesh.flags[face.other], face.other_local);
          if (special) block_faces[b].push_back(face);
        }
      }
    }
  });
  SpecialFaces out;
  for (const auto& bf : block_faces) out.faces.insert(out.faces.end(), bf.begin(), bf.end());
  block_faces = {};
  parallel::sort(out.faces.begin(), out.faces.end(), [](const SpecialFace& x, const SpecialFace& y) {
    return x.tet != y.tet ? x.tet < y.tet : x.local < y.local;
  });
  out.faces.shrink_to_fit();
  out.on_face.assign(nv, 0);
  for (const SpecialFace& f : out.faces)
    for (int k = 0; k < 4; ++k)
      if (k != f.local) out.on_face[mesh.tets[f.tet][k]] = 1;
  return out;
}

}  // namespace topotet
