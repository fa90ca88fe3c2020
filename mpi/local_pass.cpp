#include "local_pass.h"

#include <numeric>

#include "entry_points.h"
#include "mesh/mesh_model.h"

namespace topotet::mpi::detail {

namespace {

// The part as the engine's mesh, vertex refs = local indices, shared vertices frozen, `keep` pinned.
MeshModel build_part(const MeshData& data, const std::vector<std::uint8_t>& shared, const std::vector<std::uint8_t>& keep) {
  // A listed triangle or segment whose vertices are here but that is no face or edge of a local
  // tet belongs to another rank's tets (a code may list it on every rank holding its vertices).
  BuildOptions build;
  build.skip_detached_substructures = true;
  MeshModel part = build_mesh_model(data, build);
  for (VertId v = 0; v < data.vertex_count(); ++v)
    if (shared[v]) part.vertex_states[v] |= vertex_state::kFrozen | vertex_state::kPinned;
    else if (!keep.empty() && keep[v]) part.vertex_states[v] |= vertex_state::kPinned;
  return part;
}

// The vertex refs carry each vertex's index through the engine (collapses keep the staying end's
// ref; reordering and compaction move refs with their vertices), which says which input vertex
// each output vertex is. Returns the user's refs, to be put back afterwards.
std::vector<std::int32_t> number_vertices(MeshData& data) {
  std::vector<std::int32_t> user_refs = std::move(data.vertex_refs);
  data.vertex_refs.resize(data.vertex_count());
  std::iota(data.vertex_refs.begin(), data.vertex_refs.end(), 0);
  return user_refs;
}

}  // namespace

Report trial_part(DistributedMesh& mesh, const std::vector<std::uint8_t>& shared, const std::vector<std::uint8_t>& keep,
                  SimplifyOptions options, std::uint64_t target_vertices) {
  // Built exactly as simplify_part builds it (the same refs), so that the trial is the same run.
  std::vector<std::int32_t> user_refs = number_vertices(mesh.local);
  MeshModel part;
  try {
    part = build_part(mesh.local, shared, keep);
  } catch (...) {
    mesh.local.vertex_refs = std::move(user_refs);
    throw;
  }
  mesh.local.vertex_refs = std::move(user_refs);
  options.target_vertices = std::max<std::uint64_t>(target_vertices, 1);
  std::vector<VertId> map;
  return simplify(part, options, map);
}

LocalPass simplify_part(DistributedMesh& mesh, const std::vector<std::uint8_t>& shared,
                        const std::vector<std::uint8_t>& keep, SimplifyOptions options, std::uint64_t target_vertices) {
  LocalPass pass;
  MeshData data = std::move(mesh.local);
  std::vector<std::int32_t> user_refs = number_vertices(data);
  MeshModel part = build_part(data, shared, keep);
  data = MeshData{};
  options.target_vertices = std::max<std::uint64_t>(target_vertices, 1);
  std::vector<VertId> map;
  pass.report = simplify(part, options, map);
  MeshData out = part.to_mesh_data();
  part = MeshModel{};
  pass.origin.resize(out.vertex_count());
  for (VertId o = 0; o < out.vertex_count(); ++o)
    pass.origin[o] = out.vertex_refs.empty() ? 0 : static_cast<VertId>(out.vertex_refs[o]);
  std::vector<GlobalId> ids(out.vertex_count());
  for (VertId o = 0; o < out.vertex_count(); ++o) ids[o] = mesh.global_ids[pass.origin[o]];
  for (VertId i = 0; i < map.size(); ++i)
    if (map[i] != kInvalid && ids[map[i]] != mesh.global_ids[i]) pass.merges.emplace_back(mesh.global_ids[i], ids[map[i]]);
  if (user_refs.empty()) {
    out.vertex_refs.clear();
  } else {
    for (VertId o = 0; o < out.vertex_count(); ++o) out.vertex_refs[o] = user_refs[pass.origin[o]];
  }
  std::vector<int> owner(out.vertex_count());
  for (VertId o = 0; o < out.vertex_count(); ++o) owner[o] = mesh.owner[pass.origin[o]];
  mesh.local = std::move(out);
  mesh.global_ids = std::move(ids);
  mesh.owner = std::move(owner);
  return pass;
}

}  // namespace topotet::mpi::detail
