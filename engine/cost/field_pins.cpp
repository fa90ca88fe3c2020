#include "cost/field_pins.h"

#include <algorithm>

namespace topotet {

std::string compute_field_pins(const MeshModel& mesh, const std::vector<IsoLevel>& levels,
                               std::vector<std::uint32_t>& pins) {
  pins.clear();
  if (levels.empty()) return {};
  const std::size_t stride = static_cast<std::size_t>(mesh.field_stride());
  pins.assign(mesh.vertex_capacity(), 0u);
  for (const IsoLevel& level : levels) {
    int offset = 0;
    const FieldInfo* field = nullptr;
    for (const FieldInfo& f : mesh.fields) {
      if (f.name == level.field) {
        field = &f;
        break;
      }
      offset += f.components;
    }
    if (field == nullptr) return "isosurfaces: the mesh has no field named '" + level.field + "'";
    if (level.component < 0 || level.component >= field->components)
      return "isosurfaces: field '" + level.field + "' has no component " + std::to_string(level.component);
    const int k = offset + level.component;
    if (k >= kMaxPinnedComponents)
      return "isosurfaces: field component " + std::to_string(k) + " is past the " +
             std::to_string(kMaxPinnedComponents) + " that can be pinned";
    // A face carries the level's ref itself, or a stand-in for a set of refs that holds it (a face
    // listed on several surfaces, mesh_model.h SharedRefs).
    std::vector<std::int32_t> labels = {level.ref};
    for (const SharedRefs& s : mesh.shared_face_refs)
      if (std::binary_search(s.refs.begin(), s.refs.end(), level.ref)) labels.push_back(s.stand_in);
    const std::uint32_t bit = 1u << k;
    for (std::size_t t = 0; t < mesh.tet_capacity(); ++t) {
      const TetFlags f = mesh.flags[t];
      if (mesh.is_dead_tet(static_cast<TetId>(t)) || !(f & tet_flag::kSurfaceFaces)) continue;
      const SubstructureRefs& r = mesh.refs_table[mesh.tet_refs_slot[t]];
      for (int face = 0; face < 4; ++face) {
        if (!is_surface_face(f, face) || std::find(labels.begin(), labels.end(), r.face[face]) == labels.end()) continue;
        for (int i : kTetFaces[face]) {
          const VertId v = mesh.tets[t][i];
          if (mesh.field_values[v * stride + k] != level.value)
            return "isosurfaces: vertex " + std::to_string(v + 1) + " of a triangle with ref " + std::to_string(level.ref) +
                   " has " + level.field + " = " + std::to_string(mesh.field_values[v * stride + k]) +
                   ", not the level " + std::to_string(level.value) + " (embed_isosurfaces sets it exactly)";
          pins[v] |= bit;
        }
      }
    }
  }
  return {};
}

}  // namespace topotet
