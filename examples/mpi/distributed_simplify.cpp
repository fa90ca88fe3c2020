// A code whose mesh is already spread over its MPI ranks calls topotet::mpi::simplify directly.
//   mpirun -np 4 ./distributed_simplify
// Here every rank takes the tets of one slab of a generated cube-sphere (in a simulation they
// would come from its own decomposition): its DistributedMesh lists only those tets, their
// vertices with global ids, and the listed triangles, segments, corners and fields on them.
#include <cstdio>
#include <unordered_map>

#include "topotet/generate.h"
#include "topotet/mpi.h"

namespace {

// The part of `whole` made of the tets whose centroid x falls in this rank's slab.
topotet::mpi::DistributedMesh my_slab(const topotet::MeshData& whole, int rank, int ranks) {
  topotet::mpi::DistributedMesh part;
  topotet::MeshData& d = part.local;
  std::unordered_map<topotet::VertId, topotet::VertId> local_of;
  auto local = [&](topotet::VertId g) {
    auto [it, added] = local_of.emplace(g, static_cast<topotet::VertId>(d.positions.size()));
    if (added) {
      d.positions.push_back(whole.positions[g]);
      part.global_ids.push_back(g);
    }
    return it->second;
  };
  double lo = 1e300, hi = -1e300;
  for (const auto& p : whole.positions) {
    lo = std::min(lo, p[0]);
    hi = std::max(hi, p[0]);
  }
  for (std::size_t t = 0; t < whole.tet_count(); ++t) {
    const auto& v = whole.tets[t];
    const double x = 0.25 * (whole.positions[v[0]][0] + whole.positions[v[1]][0] + whole.positions[v[2]][0] +
                             whole.positions[v[3]][0]);
    const int slab = std::min(ranks - 1, static_cast<int>((x - lo) / (hi - lo) * ranks));
    if (slab != rank) continue;
    d.tets.push_back({local(v[0]), local(v[1]), local(v[2]), local(v[3])});
    d.tet_material.push_back(whole.tet_material[t]);
  }
  // Listed elements whose vertices are all here; the simplifier keeps only those on its tets.
  auto here = [&](topotet::VertId g) { return local_of.count(g) != 0; };
  for (const auto& tri : whole.triangles)
    if (here(tri.v[0]) && here(tri.v[1]) && here(tri.v[2]))
      d.triangles.push_back({{local_of[tri.v[0]], local_of[tri.v[1]], local_of[tri.v[2]]}, tri.ref});
  for (const auto& seg : whole.segments)
    if (here(seg.v[0]) && here(seg.v[1])) d.segments.push_back({{local_of[seg.v[0]], local_of[seg.v[1]]}, seg.ref});
  for (topotet::VertId c : whole.corners)
    if (here(c)) d.corners.push_back(local_of[c]);
  for (const auto& f : whole.fields) {
    topotet::VertexField lf{f.name, f.components, {}};
    for (topotet::mpi::GlobalId g : part.global_ids)
      for (int c = 0; c < f.components; ++c) lf.values.push_back(f.values[g * f.components + c]);
    d.fields.push_back(lf);
  }
  return part;
}

void run(int rank, int ranks) {
  topotet::GenerateOptions g;
  g.target_tets = 20000;
  topotet::mpi::DistributedMesh part = my_slab(topotet::generate_mesh(g), rank, ranks);
  const std::size_t my_vertices = part.global_ids.size();
  topotet::mpi::Options options;
  options.simplify.target_vertex_ratio = 0.2;  // of the global vertex count
  const topotet::mpi::Result r = topotet::mpi::simplify(MPI_COMM_WORLD, part, options);
  // part: this rank's share of the result. r.vertex_map[i]: the global id my input vertex i became
  // or merged into (a code transfers its fields back with it). r.report: reduced over the ranks.
  if (rank == 0)
    std::printf("%llu -> %llu vertices in %zu passes, %.2f s (%s)\n",
                static_cast<unsigned long long>(r.report.vertices_before),
                static_cast<unsigned long long>(r.report.vertices_after), r.passes.size(), r.report.seconds,
                topotet::to_string(r.report.status));
  std::printf("rank %d: %zu of %zu input vertices mapped, %zu tets now\n", rank, r.vertex_map.size(), my_vertices,
              part.local.tet_count());
}

}  // namespace

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  int rank = 0, ranks = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &ranks);
  int code = 0;
  try {
    run(rank, ranks);  // collective: an error throws on every rank together (topotet/mpi.h)
  } catch (const std::exception& e) {
    if (rank == 0) std::fprintf(stderr, "distributed_simplify: %s\n", e.what());
    code = 1;
  }
  MPI_Finalize();
  return code;
}
