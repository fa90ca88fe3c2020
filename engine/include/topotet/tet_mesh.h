// TetMesh: the validated working model the simplifier edits in place, built from a MeshData by
// build_tet_mesh and given back by to_mesh_data().
//
// The model's arrays are private (the engine's internal MeshModel; see ../shared/DESIGN.md,
// "Data"). Read it through the accessors below. Vertex and tet ids run over the slots, dead ones
// included: simplify() marks removed vertices and tets dead and compacts the model before it
// returns, so after simplify() every slot is live.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "topotet/mesh_data.h"

namespace topotet {

namespace detail {
struct MeshModel;  // engine-internal (engine/mesh/mesh_model.h)
}

struct FieldInfo {
  std::string name;
  int components = 1;
};

// What to_mesh_data writes besides the input's own substructures.
struct MeshExportOptions {
  // Detected feature curves as segments with ref feature_ref, marked as
  // MEDIT ridges, and detected corners as corners: for inspecting the detection (ParaView).
  bool feature_edges = false;
  std::int32_t feature_ref = 0;
};

struct BuildOptions {
  // Input whose tets are ALL negatively oriented (a common convention mismatch) is flipped.
  // Mixed orientations are always an error.
  bool reorient_inverted = true;
  // Listed triangles that are not faces of any tet, and listed segments that are not edges of any
  // tet, are an error by default. With this set they are left out of the model and listed in
  // BuildNotes instead. Gmsh's -save_all writes such elements for model surfaces and curves that
  // bound no meshed volume; they describe nothing inside the tetrahedral domain, so the simplified
  // mesh could not carry them anyway. The CLI sets this and prints a warning with the count.
  bool skip_detached_substructures = false;
};

// What build_tet_mesh accepted but did not take as given (the library never prints: callers
// decide whether to warn). Indices into MeshData::triangles / segments, increasing.
struct BuildNotes {
  std::vector<std::uint32_t> repeated_triangles;  // same face and same ref as an earlier one: kept once
  std::vector<std::uint32_t> repeated_segments;   // same edge and same ref as an earlier one: kept once
  std::vector<std::uint32_t> detached_triangles;  // no tet has this face: left out (skip_detached_substructures)
  std::vector<std::uint32_t> detached_segments;   // no tet has this edge: left out
  bool empty() const {
    return repeated_triangles.empty() && repeated_segments.empty() && detached_triangles.empty() &&
           detached_segments.empty();
  }
};

class TetMesh {
 public:
  TetMesh();  // an empty mesh
  explicit TetMesh(std::unique_ptr<detail::MeshModel> model);
  TetMesh(const TetMesh& other);
  TetMesh& operator=(const TetMesh& other);
  // A moved-from mesh may only be assigned to or destroyed.
  TetMesh(TetMesh&& other) noexcept;
  TetMesh& operator=(TetMesh&& other) noexcept;
  ~TetMesh();

  std::size_t vertex_capacity() const;  // vertex slots, dead ones included
  std::size_t tet_capacity() const;     // tet slots, dead ones included
  std::size_t live_vertex_count() const;
  std::size_t live_tet_count() const;
  bool is_dead_vertex(VertId v) const;
  bool is_dead_tet(TetId t) const;

  std::array<double, 3> position(VertId v) const;
  const std::array<VertId, 4>& tet(TetId t) const;  // positively oriented
  std::int32_t material(TetId t) const;

  // The arrays themselves, for reading without a copy; valid until the mesh changes.
  const double* positions_data() const;  // 3 doubles per vertex slot: x, y, z
  const VertId* tets_data() const;       // 4 vertex ids per tet slot
  const std::int32_t* materials_data() const;  // 1 per tet slot
  const std::vector<FieldInfo>& fields() const;
  int field_stride() const;                 // doubles per vertex in field_values_data()
  const double* field_values_data() const;  // fields interleaved in the order of fields()

  // Bytes held by the model's arrays (capacity, not size: what the process really pays).
  std::size_t memory_bytes() const;

  // The interchange form of the live part: vertices and tets renumbered densely in their current
  // order, listed triangles/segments recovered from the model (each once per ref, sorted),
  // material interfaces the input did not list and detected features omitted (unless `options`
  // asks for the features), corners/required vertices and fields kept.
  MeshData to_mesh_data(const MeshExportOptions& options = {}) const;

  // The engine's model. detail::MeshModel is complete only inside the library's sources.
  detail::MeshModel& model() { return *model_; }
  const detail::MeshModel& model() const { return *model_; }

 private:
  std::unique_ptr<detail::MeshModel> model_;
};

// Validates raw input and builds the model. Throws InputError naming the element at fault:
// non-finite coordinates, out-of-range indices, repeated vertices in a tet, zero-volume or
// inverted tets (unless all are inverted and options.reorient_inverted), faces shared by more
// than two tets, duplicate tets, triangles that are not faces of a tet and segments that are not
// edges of a tet (unless options.skip_detached_substructures), field arrays of the wrong size.
// A face (edge) listed again with the same ref is kept once and noted; listed again with another
// ref it belongs to each listed substructure. `notes`, when given, receives what was
// left out. Runs in the caller's task arena (parallel over tets and vertices). The messages count
// elements and vertices from 1, as the files do ("tet 4" is data.tets[3]).
TetMesh build_tet_mesh(const MeshData& data, const BuildOptions& options = {}, BuildNotes* notes = nullptr);

// Removes from `data` the triangles and segments that `notes` says the model left out or kept
// once (ridges renumbered), so that `data` lists exactly what the model holds: the topology
// checker then compares the simplified mesh with the same substructures.
void drop_noted_substructures(MeshData& data, const BuildNotes& notes);

}  // namespace topotet
