// The engines' hook for topotet::simplify_with_hierarchy (topotet/hierarchy.h): a log of the
// accepted collapses, in the engine's own vertex ids, with their dependencies.
//
// The engines record in batches: the parallel engine one batch per round (slot = the winner's
// position in the round's ascending winner list), the sequential engine one batch per collapse.
// record() must be called just BEFORE collapse() (it reads u's and v's old positions and fields),
// and depend() just AFTER it with the old stars St(u) and St(v) (the kernel scratch's star_u and
// star_v, which collapse() gathers and leaves): the parents are the collapses that last changed
// one of those tets. Within a batch the stencils are disjoint, so both may run concurrently for
// different slots: they write only their slot and the last_change_ entries of their own tets, and
// read entries no other slot of the batch writes. Collapse ids are the batch's first id plus the
// slot, so the log is the same for any thread count.
//
// A log can continue another run's (out of core: a piece's run continues the records of the
// levels before it, outofcore/hierarchy_spool.h): its collapse ids start at `first_id`, and
// seed_tets gives each tet the (global) id of the collapse that last changed it, so the first
// collapses of this run find their parents in the earlier runs. The driver renumbers the seeds
// with the tets (renumber_tets) and, at the end, keeps those of the live tets in their order
// (keep_live_tets), which a next run seeds from. Such a log can also hand its records over as it
// goes (set_sink: every `every` collapses, at the end of a batch, and once more by flush()), so
// that they need not stay in memory: the records then hold the collapses since the last hand-over.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include <glm/vec3.hpp>

#include "mesh/glm_convert.h"
#include "mesh/mesh_model.h"

namespace topotet {
struct Hierarchy;
}

namespace topotet::detail {

// Hierarchy::error from Hierarchy::cost (the running maximum); used after recording and reading.
void fill_running_error(Hierarchy& hierarchy);

class CollapseLog {
 public:
  CollapseLog(std::size_t tet_capacity, int field_stride, std::uint32_t first_id = 0);

  // [tet] the collapse that last changed it in an earlier run (kInvalid: none); one per tet.
  void seed_tets(std::vector<std::uint32_t> last_change);
  bool seeded() const { return seeded_; }
  // The tets renumbered (old -> new, reorder_for_locality): the seeds follow them.
  void renumber_tets(const std::vector<TetId>& tet_old2new, std::size_t tet_capacity);
  // At the end, before compact(): each live tet's last collapse, in the live tets' order (the
  // output's). The log is not used after.
  std::vector<std::uint32_t> keep_live_tets(const MeshModel& mesh) const;
  // Calls sink(*this) and clears the records once they hold `every` collapses or more (at the end
  // of a batch), and in flush(); collapse ids go on from where they were.
  void set_sink(std::function<void(const CollapseLog&)> sink, std::size_t every);
  void flush();

  void begin_batch(std::size_t slots);
  void record(std::size_t slot, const MeshModel& mesh, VertId u, VertId v, const glm::dvec3& p,
              const double* fields_after, double cost);
  void depend(std::size_t slot, const std::vector<TetId>& star_u, const std::vector<TetId>& star_v);
  // The field error bound of the slot's new star (collapse()'s return value with FieldBounds).
  void bound(std::size_t slot, float value) { slots_[slot].bound = value; }
  void end_batch();  // appends the batch's slots in order

  int field_stride() const { return stride_; }

  // The records (engine ids), in recording order.
  std::vector<VertId> u, v;
  std::vector<std::array<double, 3>> u_before, u_after, v_position;  // as Hierarchy holds them
  std::vector<double> fields_before, fields_after, cost;
  std::vector<float> error_bound;  // NaN where bound() was not called
  std::vector<std::uint32_t> parent_offsets{0}, parents;

 private:
  struct Slot {
    VertId u = kInvalid, v = kInvalid;
    std::array<double, 3> u_before{}, u_after{}, v_position{};
    double cost = 0.0;
    float bound = 0.0f;
    std::vector<std::uint32_t> parents;  // capacity kept between batches: no allocation per collapse
  };
  int stride_;
  std::uint32_t first_id_;  // + handed_over_: the id of the first collapse in the records
  std::uint64_t handed_over_ = 0;
  std::function<void(const CollapseLog&)> sink_;
  std::size_t sink_every_ = 0;
  bool seeded_ = false;
  std::vector<std::uint32_t> last_change_;  // [tet] the latest collapse that changed it (kInvalid: none)
  std::vector<Slot> slots_;
  std::vector<double> slot_fields_;  // [slot * 2 * stride_]: before, then after
  std::size_t batch_size_ = 0;
};

}  // namespace topotet::detail
