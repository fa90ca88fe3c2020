// The public TetMesh: a handle owning the engine's MeshModel. Every entry point of the public
// API unwraps it once and hands the model to the engine.
#include "entry_points.h"
#include "mesh/mesh_model.h"
#include "topotet/hierarchy.h"

namespace topotet {

TetMesh::TetMesh() : model_(std::make_unique<MeshModel>()) {}
TetMesh::TetMesh(std::unique_ptr<MeshModel> model) : model_(std::move(model)) {}
TetMesh::TetMesh(const TetMesh& other) : model_(std::make_unique<MeshModel>(*other.model_)) {}
TetMesh& TetMesh::operator=(const TetMesh& other) {
  if (this != &other) model_ = std::make_unique<MeshModel>(*other.model_);
  return *this;
}
TetMesh::TetMesh(TetMesh&& other) noexcept = default;
TetMesh& TetMesh::operator=(TetMesh&& other) noexcept = default;
TetMesh::~TetMesh() = default;

std::size_t TetMesh::vertex_capacity() const { return model_->vertex_capacity(); }
std::size_t TetMesh::tet_capacity() const { return model_->tet_capacity(); }
std::size_t TetMesh::live_vertex_count() const { return model_->live_vertex_count(); }
std::size_t TetMesh::live_tet_count() const { return model_->live_tet_count(); }
bool TetMesh::is_dead_vertex(VertId v) const { return model_->is_dead_vertex(v); }
bool TetMesh::is_dead_tet(TetId t) const { return model_->is_dead_tet(t); }

std::array<double, 3> TetMesh::position(VertId v) const {
  const glm::dvec3& p = model_->positions[v];
  return {p.x, p.y, p.z};
}
const std::array<VertId, 4>& TetMesh::tet(TetId t) const { return model_->tets[t]; }
std::int32_t TetMesh::material(TetId t) const { return model_->material[t]; }

const double* TetMesh::positions_data() const {
  static_assert(sizeof(glm::dvec3) == 3 * sizeof(double), "positions are 3 packed doubles");
  return model_->positions.empty() ? nullptr : &model_->positions[0].x;
}
const VertId* TetMesh::tets_data() const { return model_->tets.empty() ? nullptr : model_->tets[0].data(); }
const std::int32_t* TetMesh::materials_data() const {
  return model_->material.empty() ? nullptr : model_->material.data();
}
const std::vector<FieldInfo>& TetMesh::fields() const { return model_->fields; }
int TetMesh::field_stride() const { return model_->field_stride(); }
const double* TetMesh::field_values_data() const { return model_->field_values.data(); }

std::size_t TetMesh::memory_bytes() const { return model_->memory_bytes(); }
MeshData TetMesh::to_mesh_data(const MeshExportOptions& options) const { return model_->to_mesh_data(options); }

TetMesh build_tet_mesh(const MeshData& data, const BuildOptions& options, BuildNotes* notes) {
  return TetMesh(std::make_unique<MeshModel>(build_mesh_model(data, options, notes)));
}

Report simplify(TetMesh& mesh, const SimplifyOptions& options) noexcept { return simplify(mesh.model(), options); }
Report simplify(TetMesh& mesh, const SimplifyOptions& options, std::vector<VertId>& vertex_map) noexcept {
  return simplify(mesh.model(), options, vertex_map);
}
Report simplify_with_hierarchy(TetMesh& mesh, const SimplifyOptions& options, Hierarchy& hierarchy) noexcept {
  return simplify_with_hierarchy(mesh.model(), options, hierarchy);
}
FeatureStats detect_features(TetMesh& mesh, double angle_degrees) { return detect_features(mesh.model(), angle_degrees); }
FeatureStats detect_features(TetMesh& mesh, double angle_degrees, double scale) {
  return detect_features(mesh.model(), angle_degrees, scale);
}
double feature_scale(const TetMesh& mesh, const SimplifyOptions& options) { return feature_scale(mesh.model(), options); }

}  // namespace topotet
