// simplify_with_hierarchy (topotet/hierarchy.h): runs simplify() with the collapse log
// (hierarchy/hierarchy_log.h) and translates the log to input vertex ids. Why replaying a
// downward-closed set of the recorded collapses is exact: hierarchy/hierarchy_log.cpp.
#include <new>
#include <string>
#include <vector>

#include "engines.h"
#include "hierarchy/hierarchy_log.h"
#include "topotet/hierarchy.h"

namespace topotet {

Report simplify_with_hierarchy(MeshModel& mesh, const SimplifyOptions& options, Hierarchy& hierarchy) noexcept {
  Report report;
  try {
    hierarchy = Hierarchy{};
    hierarchy.original = mesh.to_mesh_data();
    hierarchy.field_stride = mesh.field_stride();
    // to_mesh_data numbers the live vertices densely in their order: the records' ids.
    std::vector<VertId> dense(mesh.vertex_capacity(), kInvalid);
    VertId next = 0;
    for (VertId x = 0; x < mesh.vertex_capacity(); ++x)
      if (!mesh.is_dead_vertex(x)) dense[x] = next++;
    detail::CollapseLog log(mesh.tet_capacity(), mesh.field_stride());
    std::vector<VertId> new2old;
    report = detail::simplify_recorded(mesh, options, log, new2old);
    if (report.status == Status::kInvalidInput) return report;
    auto input_id = [&](VertId x) { return new2old.empty() ? dense[x] : dense[new2old[x]]; };
    const std::size_t n = log.u.size();
    hierarchy.u.resize(n);
    hierarchy.v.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      hierarchy.u[i] = input_id(log.u[i]);
      hierarchy.v[i] = input_id(log.v[i]);
    }
    hierarchy.u_before = std::move(log.u_before);
    hierarchy.u_after = std::move(log.u_after);
    hierarchy.v_position = std::move(log.v_position);
    hierarchy.fields_before = std::move(log.fields_before);
    hierarchy.fields_after = std::move(log.fields_after);
    hierarchy.cost = std::move(log.cost);
    hierarchy.error_bound = std::move(log.error_bound);
    hierarchy.parent_offsets = std::move(log.parent_offsets);
    hierarchy.parents = std::move(log.parents);
    detail::fill_running_error(hierarchy);
  } catch (const std::bad_alloc&) {
    report.status = Status::kOutOfMemory;
    report.message = "out of memory while recording the hierarchy";
  } catch (const std::exception& e) {
    report.status = Status::kInternalError;
    report.message = std::string("internal error while recording the hierarchy: ") + e.what();
  }
  return report;
}

}  // namespace topotet
