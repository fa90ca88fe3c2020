// simplify_out_of_core: the levels of paper 002's binary hierarchy (topotet/out_of_core.h).
//
//   cut the input into P pieces (cut.h), P from the memory limit (memory_budget.h)
//   level 0: every piece simplified with its border frozen, removing its share of the interior
//   level l = 1, 2, ...: pieces 2i and 2i + 1 (Morton neighbours) merged, when together they fit,
//            and the merged piece simplified: its former common border is interior now
//   until one piece is left, or no pair fits; then the output is written from what is left.
// How much each level removes: a piece's region is the vertices of the input it alone holds (its
// interior at level 0; a merge adds the two regions and the border they shared). Level l keeps
// d_l of its region's vertices: d_l = max(r, 3/8 * fill / 2^l), r the asked ratio, fill how much
// larger than the cut's pieces a piece may be (1 with --pieces), so that a merged pair still fits,
// and the last piece goes to the target. The work is spread over the levels instead of done at
// level 0: a level-0 piece sees only its own part of the mesh, so cutting it straight to r would
// spend its vertices by its local ranking of the collapses, not the whole mesh's; each merge
// widens the ranking, and the last, over the whole mesh, chooses the final collapses as in core.
// A level that can merge no pair (the limit) ends the merges: every piece left then goes to r.
// At that last level (or the last merge level) pieces left apart would keep their common borders
// as the input had them; a seam between every two neighbours (seams.h: a band of each around
// their border, made one piece) lets that border be simplified too, within the same level.
// The ranking stays the whole run's because each vertex's quadric travels with its piece from
// level to level (Piece::quadrics, SimplifyOptions::quadrics_in/_out): a level that rebuilt them
// from its already simplified input would measure errors against that input, not the original
// (measured: +32% field RMS at 16 pieces on the cube-sphere, +2% with them; docs/performance.md).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <numeric>
#include <optional>
#include <set>
#include <filesystem>

#include "cut.h"
#include "engines.h"
#include "entry_points.h"
#include "hierarchy/hierarchy_log.h"
#include "hierarchy_spool.h"
#include "memory_budget.h"
#include "mesh/mesh_model.h"
#include "piece.h"
#include "piece_slot.h"
#include "seams.h"
#include "topotet/cell_fields.h"
#include "scratch.h"
#include "topotet/error.h"
#include "topotet/io.h"
#include "topotet/medit_stream.h"
#include "topotet/out_of_core.h"
#include "topotet/vertex_map_file.h"
#include "vertex_map_log.h"

namespace topotet {

namespace {

using namespace ooc;
using Clock = std::chrono::steady_clock;

double since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

void refuse_unsupported(const SimplifyOptions& o) {
  if (!o.isosurfaces.empty())
    throw InputError("isosurfaces are not available out of core: embed them in core first (topotet simplify "
                     "--isosurface at --ratio 1), then simplify that mesh out of core");
  if (!(o.target_vertex_ratio > 0.0 && o.target_vertex_ratio <= 1.0))
    throw InputError("target_vertex_ratio must be in (0, 1]");
}

// Field error bounds out of core: every input vertex is a sample of exactly one piece (the first,
// at level 0, that holds it: a border vertex is in several), in the first of that piece's tets
// that has it (bound 0 there), as an in-core run takes them; from then on the samples travel with
// their tets (Piece::samples), level after level, and stay exact over the input's vertices. A
// piece's border is frozen, so its samples never cross into another piece.
struct FieldSampling {
  std::vector<bool> taken;                // [global vertex] a sample of some piece already
  std::vector<double> range, magnitude;   // [component] over the input's used vertices (the cut)
};

void take_samples(const MeshModel& model, const std::vector<GlobalId>& ids, FieldSampling& sampling,
                  FieldBoundSamples& out) {
  const auto k = static_cast<std::size_t>(model.field_stride());
  out = FieldBoundSamples{};
  out.components = model.field_stride();
  out.range = sampling.range;
  out.magnitude = sampling.magnitude;
  out.bounds.assign(model.tets.size() * k, 0.0f);
  for (TetId t = 0; t < model.tets.size(); ++t)
    for (VertId x : model.tets[t]) {
      if (sampling.taken[ids[x]]) continue;
      sampling.taken[ids[x]] = true;
      for (int d = 0; d < 3; ++d) out.positions.push_back(model.positions[x][d]);
      out.values.insert(out.values.end(), model.field_values.begin() + static_cast<std::ptrdiff_t>(x * k),
                        model.field_values.begin() + static_cast<std::ptrdiff_t>((x + 1) * k));
      out.tet.push_back(t);
    }
}

// What one piece's run changed, for the totals.
struct PieceRun {
  Report report;
  std::uint64_t removed = 0;
};

// Simplifies `piece` with the vertices other pieces hold frozen, removing at most `remove`.
// Cell fields are not in the engine's model: they are remapped from the piece as it was onto the
// simplified piece (topotet/cell_fields.h; exact overlaps: the piece's region is the same before and
// after, its border frozen), so an extensive array's sum is conserved level after level.
// With a vertex map asked for, the vertices the run merged go to `map` (global ids). With field
// bounds (`sampling`), the piece's samples go through the run (taken first, at level 0). With a
// hierarchy file (`spool`), the run's collapses are recorded, continuing the run's ids from the
// tets' last collapses (hierarchy_spool.h).
PieceRun simplify_piece(Piece& piece, const std::vector<std::uint8_t>& holders, SimplifyOptions options,
                        std::uint64_t remove, const CellRemapOptions& cell_remap, VertexMapLog* map,
                        FieldSampling* sampling, HierarchySpool* spool) {
  PieceRun run;
  MeshData& data = piece.mesh;
  const std::size_t before = data.positions.size();
  // A piece with quadrics and nothing to remove is left as it is; one without is run all the same
  // (no collapse), for its quadrics.
  if (remove == 0 && !piece.quadrics.empty()) return run;
  // The vertex refs carry each vertex's index through the engine (mpi/local_pass.cpp does the same).
  std::vector<std::int32_t> user_refs = std::move(data.vertex_refs);
  data.vertex_refs.resize(before);
  std::iota(data.vertex_refs.begin(), data.vertex_refs.end(), 0);
  MeshModel model = build_mesh_model(data);
  MeshData cells_before;
  if (!data.cell_fields.empty()) {
    cells_before.positions = std::move(data.positions);
    cells_before.tets = std::move(data.tets);
    cells_before.tet_material = std::move(data.tet_material);
    cells_before.cell_fields = std::move(data.cell_fields);
  }
  data = MeshData{};
  for (VertId v = 0; v < before; ++v)
    if (holders[piece.global_ids[v]] >= 2) model.vertex_states[v] |= vertex_state::kFrozen | vertex_state::kPinned;
  options.target_vertices = std::max<std::uint64_t>(before - std::min<std::uint64_t>(remove, before), 1);
  std::vector<double> quadrics_out;
  options.quadrics_in = piece.quadrics.empty() ? nullptr : &piece.quadrics;
  options.quadrics_out = &quadrics_out;
  options.field_samples = nullptr;
  if (sampling != nullptr) {
    if (piece.samples.components == 0) take_samples(model, piece.global_ids, *sampling, piece.samples);
    options.field_samples = &piece.samples;
  }
  std::vector<VertId> local_map;
  std::optional<detail::CollapseLog> log;
  std::vector<VertId> new2old;  // the log's vertex ids -> the piece's
  std::vector<std::uint32_t> last_collapse;
  // The log's vertex ids -> global ids: new2old is set (by the driver's renumbering) before the
  // first collapse, so before the first hand-over.
  std::vector<GlobalId> global;
  const auto to_global = [&]() -> const std::vector<GlobalId>& {
    if (global.empty())
      for (VertId x = 0; x < (new2old.empty() ? before : new2old.size()); ++x)
        global.push_back(piece.global_ids[new2old.empty() ? x : new2old[x]]);
    return global;
  };
  if (spool != nullptr) {
    log.emplace(model.tet_capacity(), model.field_stride(), spool->next_id());
    if (!piece.last_collapse.empty()) log->seed_tets(std::move(piece.last_collapse));
    // The records go to the spool as they come (kHierarchyBatch collapses at a time), not at the
    // end of the piece: memory_budget.h counts that batch, not the piece's collapses.
    log->set_sink([&](const detail::CollapseLog& records) { spool->append(records, to_global()); }, kHierarchyBatch);
    run.report = detail::simplify_recorded(model, options, *log, new2old, &last_collapse);
  } else {
    run.report = map != nullptr ? simplify(model, options, local_map) : simplify(model, options);
  }
  if (run.report.status == Status::kInvalidInput || run.report.status == Status::kInternalError ||
      run.report.status == Status::kOutOfMemory || run.report.status == Status::kCancelled)
    throw InputError("out-of-core piece: " + run.report.message);
  if (log) {
    log->flush();
    log.reset();
    piece.last_collapse = std::move(last_collapse);
  }
  MeshData out = model.to_mesh_data();
  model = MeshModel{};
  if (!cells_before.cell_fields.empty()) remap_cell_fields(cells_before, out, cell_remap);
  std::vector<GlobalId> ids(out.positions.size());
  for (VertId o = 0; o < out.positions.size(); ++o) ids[o] = piece.global_ids[out.vertex_refs[o]];
  if (user_refs.empty()) {
    out.vertex_refs.clear();
  } else {
    for (VertId o = 0; o < out.positions.size(); ++o) out.vertex_refs[o] = user_refs[out.vertex_refs[o]];
  }
  out.group_names.clear();
  run.removed = before - out.positions.size();
  if (map != nullptr) {
    std::vector<std::pair<GlobalId, GlobalId>> merged;
    merged.reserve(run.removed);
    for (VertId v = 0; v < local_map.size(); ++v)
      if (local_map[v] != kInvalid && ids[local_map[v]] != piece.global_ids[v]) merged.push_back({piece.global_ids[v], ids[local_map[v]]});
    map->record_merges(std::move(merged));
  }
  piece.quadric_doubles = out.positions.empty() ? 0 : static_cast<std::uint32_t>(quadrics_out.size() / out.positions.size());
  if (piece.quadric_doubles * out.positions.size() != quadrics_out.size()) piece.quadric_doubles = 0;
  piece.quadrics = piece.quadric_doubles != 0 ? std::move(quadrics_out) : std::vector<double>{};
  // A border vertex's quadric holds the piece's border faces as if they were the mesh's boundary
  // (plane quadrics of a surface that is not there): the next level builds it anew from its star
  // then (NaN: simplify.h). Frozen, it has absorbed no other vertex, so nothing else is lost.
  for (VertId o = 0; o < ids.size() && piece.quadric_doubles != 0; ++o)
    if (holders[ids[o]] >= 2) piece.quadrics[std::size_t{o} * piece.quadric_doubles] = std::numeric_limits<double>::quiet_NaN();
  piece.mesh = std::move(out);
  piece.global_ids = std::move(ids);
  return run;
}

std::uint64_t folder_bytes(const std::string& folder) {
  std::uint64_t total = 0;
  std::error_code ec;
  for (const auto& e : std::filesystem::directory_iterator(folder, ec))
    if (e.is_regular_file(ec)) total += e.file_size(ec);
  return total;
}

// The output written from several pieces, MEDIT, streaming: each vertex once (from the first
// piece that holds it), every tet, listed triangles and edges on the borders once.
void write_pieces(const std::string& output, const ScratchFolder& scratch, const std::vector<PieceSlot>& slots,
                  std::uint64_t input_vertices, const CutResult& cut, VertexMapLog* vertex_map) {
  if (format_from_path(output) != MeshFormat::kMedit)
    throw InputError(output + ": the memory limit kept " + std::to_string(slots.size()) +
                     " pieces apart, and several pieces are written as MEDIT (.mesh, .meshb) only: give a .mesh output "
                     "or a larger --memory-limit");
  std::vector<VertId> out_index(input_vertices, kInvalid);
  std::vector<std::pair<std::uint64_t, std::uint64_t>> owned(slots.size());  // [slot] out ids it assigns
  std::uint64_t vertices = 0, tets = 0;
  std::set<std::array<VertId, 4>> triangle_keys;
  std::set<std::array<VertId, 3>> segment_keys;
  std::vector<Triangle> triangles;
  std::vector<Segment> segments;
  std::vector<std::uint32_t> ridges;
  std::set<VertId> corners, required;
  for (std::size_t s = 0; s < slots.size(); ++s) {
    const Piece piece = load_piece(scratch.piece_path(slots[s].file));
    owned[s].first = vertices;
    std::vector<VertId> map(piece.global_ids.size());
    for (VertId v = 0; v < piece.global_ids.size(); ++v) {
      VertId& o = out_index[piece.global_ids[v]];
      if (o == kInvalid) o = static_cast<VertId>(vertices++);
      map[v] = o;
    }
    owned[s].second = vertices;
    tets += piece.mesh.tets.size();
    for (const Triangle& t : piece.mesh.triangles) {
      Triangle o{{map[t.v[0]], map[t.v[1]], map[t.v[2]]}, t.ref};
      std::array<VertId, 4> key = {o.v[0], o.v[1], o.v[2], static_cast<VertId>(t.ref)};
      std::sort(key.begin(), key.begin() + 3);
      if (triangle_keys.insert(key).second) triangles.push_back(o);
    }
    std::vector<std::uint32_t> segment_out(piece.mesh.segments.size());
    for (std::size_t i = 0; i < piece.mesh.segments.size(); ++i) {
      const Segment& g = piece.mesh.segments[i];
      Segment o{{map[g.v[0]], map[g.v[1]]}, g.ref};
      const std::array<VertId, 3> key = {std::min(o.v[0], o.v[1]), std::max(o.v[0], o.v[1]), static_cast<VertId>(g.ref)};
      if (segment_keys.insert(key).second) {
        segment_out[i] = static_cast<std::uint32_t>(segments.size());
        segments.push_back(o);
        if (std::binary_search(piece.mesh.ridges.begin(), piece.mesh.ridges.end(), static_cast<std::uint32_t>(i)))
          ridges.push_back(segment_out[i]);
      }
    }
    for (VertId v : piece.mesh.corners) corners.insert(map[v]);
    for (VertId v : piece.mesh.required_vertices) required.insert(map[v]);
  }
  if (vertex_map != nullptr) vertex_map->record_output_index(out_index);
  MeditStreamWriter writer(output, cut.vertex_fields, cut.cell_fields);
  writer.begin_vertices(vertices);
  const int vstride = cut.counts.vertex_stride, cstride = cut.counts.cell_stride;
  std::vector<double> values(std::max(vstride, cstride));
  for (std::size_t s = 0; s < slots.size(); ++s) {
    const Piece piece = load_piece(scratch.piece_path(slots[s].file));
    for (VertId v = 0; v < piece.global_ids.size(); ++v) {
      const VertId o = out_index[piece.global_ids[v]];
      if (o < owned[s].first || o >= owned[s].second) continue;
      for (std::size_t f = 0, at = 0; f < piece.mesh.fields.size(); ++f) {
        const int c = piece.mesh.fields[f].components;
        for (int k = 0; k < c; ++k) values[at++] = piece.mesh.fields[f].values[std::size_t{v} * c + k];
      }
      writer.vertex(piece.mesh.positions[v], piece.mesh.vertex_refs.empty() ? 0 : piece.mesh.vertex_refs[v],
                    vstride > 0 ? values.data() : nullptr);
    }
  }
  writer.begin_tets(tets);
  for (std::size_t s = 0; s < slots.size(); ++s) {
    const Piece piece = load_piece(scratch.piece_path(slots[s].file));
    for (std::size_t t = 0; t < piece.mesh.tets.size(); ++t) {
      const auto& tv = piece.mesh.tets[t];
      for (std::size_t f = 0, at = 0; f < piece.mesh.cell_fields.size(); ++f) {
        const int c = piece.mesh.cell_fields[f].components;
        for (int k = 0; k < c; ++k) values[at++] = piece.mesh.cell_fields[f].values[t * c + k];
      }
      writer.tet({out_index[piece.global_ids[tv[0]]], out_index[piece.global_ids[tv[1]]],
                  out_index[piece.global_ids[tv[2]]], out_index[piece.global_ids[tv[3]]]},
                 piece.mesh.tet_material[t], cstride > 0 ? values.data() : nullptr);
    }
  }
  writer.begin_triangles(triangles.size());
  for (const Triangle& t : triangles) writer.triangle(t);
  writer.begin_segments(segments.size());
  for (const Segment& s : segments) writer.segment(s);
  writer.begin_ridges(ridges.size());
  for (std::uint32_t r : ridges) writer.ridge(r);
  writer.begin_corners(corners.size());
  for (VertId v : corners) writer.corner(v);
  writer.begin_required_vertices(required.size());
  for (VertId v : required) writer.required_vertex(v);
  writer.commit();
}

std::string parent_folder(const std::string& path) {
  const std::filesystem::path p(path);
  const std::filesystem::path parent = p.parent_path();
  return parent.empty() ? std::string(".") : parent.string();
}

}  // namespace

OutOfCoreReport simplify_out_of_core(const std::string& input, const std::string& output,
                                     const SimplifyOptions& options, const OutOfCoreOptions& ooc) {
  const auto start = Clock::now();
  refuse_unsupported(options);
  if (!ooc.vertex_map_path.empty()) check_vertex_map_path(ooc.vertex_map_path);
  if (!ooc.hierarchy_path.empty() && !ooc.vertex_map_path.empty())
    throw InputError("a hierarchy file and a vertex map exclude each other (as in core): the hierarchy's levels are "
                     "extracted with topotet extract, which maps their vertices");
  if (const MeshFormat f = format_from_path(input); f != MeshFormat::kMedit && f != MeshFormat::kGmsh)
    throw InputError(input + ": out of core streams MEDIT (.mesh, .meshb) and Gmsh MSH 4.1 (.msh), optionally .gz: convert it "
                     "first (topotet convert " + input + " in.mesh), or run in core without --memory-limit");
  if (ooc.memory_limit_bytes == 0 && ooc.pieces == 0 && ooc.piece_tets == 0)
    throw InputError("out of core needs a memory limit (--memory-limit) or a piece count");
  if (ooc.pieces != 0 && (ooc.pieces > kMaxPieces || (ooc.pieces & (ooc.pieces - 1)) != 0))
    throw InputError("the piece count must be a power of two up to " + std::to_string(kMaxPieces));
  const auto say = [&](const std::string& s) {
    if (ooc.log) ooc.log(s);
  };
  OutOfCoreReport result;
  Report& report = result.report;
  MemoryBudget budget;
  budget.limit = ooc.memory_limit_bytes;
  budget.field_samples = options.keeps_field_bounds();
  budget.hierarchy = !ooc.hierarchy_path.empty();
  budget.baseline = budget_baseline(resident_bytes());
  // Pieces of bounded size: from the memory limit, or forced (OutOfCoreOptions::piece_tets).
  const bool limited = budget.limit > 0 || ooc.piece_tets > 0;

  ScratchFolder scratch(ooc.scratch_parent.empty() ? parent_folder(output) : ooc.scratch_parent);
  say("scratch folder " + scratch.path());
  std::optional<HierarchySpool> spool;
  if (!ooc.hierarchy_path.empty()) spool.emplace(scratch);
  std::uint64_t piece_limit = 0;
  const auto choose = [&](const InputCounts& counts) -> std::uint32_t {
    piece_limit = budget.limit > 0 ? budget.piece_tets(counts) : counts.tets;
    if (ooc.piece_tets > 0) piece_limit = std::min(piece_limit, ooc.piece_tets);
    if (ooc.pieces != 0) return ooc.pieces;
    std::uint32_t pieces = 1;
    while (pieces < kMaxPieces && counts.tets > pieces * piece_limit) pieces *= 2;
    if (counts.tets > pieces * piece_limit)
      throw InputError("--memory-limit " + format_bytes(budget.limit) + " would need more than " +
                       std::to_string(kMaxPieces) + " pieces for " + std::to_string(counts.tets) + " tets");
    return pieces;
  };
  const auto on_vertices = [&](std::uint64_t vertices, std::uint64_t reader_bytes) {
    if (budget.limit > 0) budget.check_vertices(vertices, reader_bytes, input);
    return budget.limit > 0;
  };
  const auto cut_start = Clock::now();
  CutResult cut = cut_input(input, scratch, choose, ooc.log, on_vertices, ooc.cell_remap, spool ? &*spool : nullptr);
  result.cut_seconds = since(cut_start);
  result.pieces = cut.pieces;
  result.piece_tet_limit = piece_limit;
  result.scratch_peak_bytes = folder_bytes(scratch.path());
  say("cut into " + std::to_string(cut.pieces) + " pieces (at most " + std::to_string(piece_limit) + " tets each) in " +
      std::to_string(result.cut_seconds) + " s");

  std::vector<std::uint8_t>& holders = cut.holders;
  std::uint64_t input_vertices = 0;
  for (std::uint8_t h : holders) input_vertices += h != 0;
  std::optional<VertexMapLog> map;
  if (!ooc.vertex_map_path.empty()) map.emplace(scratch.file_path("vertex-map.bin"), holders.size());
  std::optional<FieldSampling> sampling;
  if (options.keeps_field_bounds() && cut.counts.vertex_stride > 0) {
    sampling.emplace();
    sampling->taken.assign(holders.size(), false);
    for (int c = 0; c < cut.counts.vertex_stride; ++c) {
      const double lo = cut.used_min[c], hi = cut.used_max[c];
      sampling->range.push_back(hi > lo ? hi - lo : 1.0);  // a constant component divides by 1, as in core
      sampling->magnitude.push_back(cut.used_magnitude[c]);
    }
  }
  report.vertices_before = input_vertices;
  report.tets_before = cut.counts.tets;
  const std::uint64_t target = std::max<std::uint64_t>(
      4, options.target_vertices != 0
             ? options.target_vertices
             : static_cast<std::uint64_t>(std::llround(options.target_vertex_ratio * static_cast<double>(input_vertices))));
  // Tolerance H shared by the levels (topotet/out_of_core.h): h_0 = H / 2, the merges H / (2 L).
  const double H = options.tolerance > 0.0 ? options.tolerance : options.tolerance_rel * cut.diagonal;
  report.tolerance = report.tolerance_asked = H;
  report.min_quality_used = report.min_quality_lowest = options.min_quality;
  report.min_dihedral_used = report.min_dihedral_lowest = options.min_dihedral;
  int merge_levels = 0;
  while ((1u << merge_levels) < cut.pieces) ++merge_levels;
  const auto level_tolerance = [&](int level) {
    if (merge_levels == 0) return H;
    return level == 0 ? H / 2 : H / (2 * merge_levels);
  };
  SimplifyOptions base = options;
  base.cost_units = &cut.units;
  base.target_vertex_ratio = 1.0;
  // The limits hold as given while there are pieces: a piece stops short of its level's share
  // instead of relaxing them, since the floors would then differ from piece to piece
  // (SimplifyOptions::relax_tolerance, relax_quality, relax_features). The run of the last level,
  // when it holds the whole mesh in one piece, relaxes them as in core (its share of H doubles:
  // the levels' shares still add up to the H the report gives).
  base.relax_tolerance = false;
  base.relax_quality = false;
  base.relax_features = false;

  std::vector<PieceSlot> slots(cut.pieces);
  std::uint64_t largest_cut_piece = 1;
  for (std::uint32_t p = 0; p < cut.pieces; ++p) {
    slots[p] = {p, cut.piece_tets[p], 0};
    largest_cut_piece = std::max(largest_cut_piece, cut.piece_tets[p]);
  }
  std::uint64_t live = input_vertices;
  const double ratio = static_cast<double>(target) / static_cast<double>(std::max<std::uint64_t>(input_vertices, 1));
  const double fill =
      limited && ooc.pieces == 0 ? std::max(1.0, static_cast<double>(piece_limit) / static_cast<double>(largest_cut_piece)) : 1.0;
  const auto kept_fraction = [&](int level) { return std::clamp(0.375 * fill / std::ldexp(1.0, level), ratio, 1.0); };
  bool finishing = false;  // no pair could merge: the pieces left go to the ratio

  // At most merge_levels merges, or fewer and the finishing level: their tolerances add up to H / 2.
  for (int level = 0; level <= merge_levels; ++level) {
    const auto level_start = Clock::now();
    OutOfCoreLevel stats;
    stats.tolerance = level_tolerance(level);
    SimplifyOptions o = base;
    o.tolerance = stats.tolerance;
    o.tolerance_rel = 0.0;
    if (H == 0.0) o.tolerance = 0.0;
    // The steps of this level: at level 0 every piece is run; later, each merged pair (a, b) is
    // run and a piece left apart (or the odd one out) is carried unchanged (a = b = -1).
    struct Step {
      PieceSlot slot;
      int a = -1, b = -1;
    };
    std::vector<Step> steps;
    if (level == 0) {
      for (std::size_t i = 0; i < slots.size(); ++i) steps.push_back({slots[i], static_cast<int>(i), -1});
    } else {
      bool merged_any = false;
      // At the last merge level a piece that is not merged is still simplified, to the ratio.
      const bool simplify_alone = level == merge_levels;
      for (std::size_t i = 0; i < slots.size(); i += 2) {
        if (i + 1 == slots.size()) {
          steps.push_back({slots[i], simplify_alone ? static_cast<int>(i) : -1});
        } else if (limited && slots[i].tets + slots[i + 1].tets > piece_limit) {
          ++stats.unmerged;
          steps.push_back({slots[i], simplify_alone ? static_cast<int>(i) : -1});
          steps.push_back({slots[i + 1], simplify_alone ? static_cast<int>(i + 1) : -1});
        } else {
          steps.push_back({{slots[i].file, slots[i].tets + slots[i + 1].tets}, static_cast<int>(i), static_cast<int>(i + 1)});
          merged_any = true;
        }
      }
      if (!merged_any) {
        finishing = true;
        steps.clear();
        for (std::size_t i = 0; i < slots.size(); ++i) steps.push_back({slots[i], static_cast<int>(i), -1});
      }
    }
    const bool last = steps.size() == 1;
    bool seamed = false;
    // The last level with pieces left apart: the pairs that fit are merged first, then every two
    // pieces that share a border get a seam (seams.h), and all are run, each to the ratio.
    if (limited && !last && (finishing || level == merge_levels)) {
      std::vector<PieceSlot> pieces;
      for (Step& step : steps) {
        if (step.b >= 0) {
          PieceSlot merged;
          Piece piece = merge_slots(scratch, holders, slots[step.a], slots[step.b], merged);
          merged.tets = piece.mesh.tets.size();
          save_piece(scratch.piece_path(merged.file), piece);
          step.slot = merged;
        }
        pieces.push_back(step.slot);
      }
      Seams seams = cut_seams(std::move(pieces), scratch, holders, piece_limit);
      seamed = true;
      stats.seams = seams.made;
      stats.seams_declined = seams.declined;
      steps.clear();
      for (std::size_t i = 0; i < seams.slots.size(); ++i) steps.push_back({seams.slots[i], static_cast<int>(i), -1});
      result.scratch_peak_bytes = std::max(result.scratch_peak_bytes, folder_bytes(scratch.path()));
    }
    const double kept = finishing || level == merge_levels ? ratio : kept_fraction(level);
    std::vector<PieceSlot> next;
    for (std::size_t s = 0; s < steps.size(); ++s) {
      Step& step = steps[s];
      PieceSlot& slot = step.slot;
      if (step.a < 0) {
        next.push_back(slot);
        continue;
      }
      Piece piece;
      if (step.b < 0) {
        piece = load_piece(scratch.piece_path(slot.file));
        if (level == 0) slot.region = interior_vertices(piece, holders);
      } else {
        piece = merge_slots(scratch, holders, slots[step.a], slots[step.b], slot);
      }
      const std::uint64_t interior = interior_vertices(piece, holders);
      auto keep = static_cast<std::uint64_t>(std::llround(kept * static_cast<double>(slot.region)));
      keep -= std::min(keep, slot.kept_frozen);
      std::uint64_t remove = interior > keep ? interior - keep : 0;
      if (last) remove = live > target ? live - target : 0;
      // Each piece's share is rounded; the level's last run takes what the roundings left (one
      // vertex a piece at most: not what pieces that stopped short of their share left).
      if (seamed && s + 1 == steps.size() && live > target)
        remove = std::max(remove, std::min(live - target, remove + steps.size()));
      stats.largest_piece_tets = std::max<std::uint64_t>(stats.largest_piece_tets, piece.mesh.tets.size());
      SimplifyOptions piece_options = o;
      if (last) {  // the whole mesh: the limits relax as in core
        piece_options.relax_tolerance = options.relax_tolerance;
        piece_options.relax_quality = options.relax_quality;
        piece_options.relax_features = options.relax_features;
      }
      const PieceRun run = simplify_piece(piece, holders, piece_options, remove, ooc.cell_remap, map ? &*map : nullptr,
                                          sampling ? &*sampling : nullptr, spool ? &*spool : nullptr);
      add_run_counts(report, run.report);
      if (!run.report.relaxations.empty()) {
        // The run's H is this level's share: the run's H is the other levels' shares plus it.
        const double others = report.tolerance - stats.tolerance;
        for (Relaxation x : run.report.relaxations) {
          if (std::string(x.limit) == "tolerance") {
            x.from += others;
            x.to += others;
          }
          report.relaxations.push_back(x);
        }
        if (o.tolerance > 0.0) {
          stats.tolerance = run.report.tolerance;
          report.tolerance = others + run.report.tolerance;
        }
        report.min_quality_used = run.report.min_quality_used;
        report.min_dihedral_used = run.report.min_dihedral_used;
        report.min_quality_lowest = run.report.min_quality_lowest;
        report.min_dihedral_lowest = run.report.min_dihedral_lowest;
        report.features_dropped += run.report.features_dropped;
      }
      if (run.report.field_bounds) {
        slot.field_bound = run.report.field_bound;
        report.field_bounds_bytes = std::max(report.field_bounds_bytes, run.report.field_bounds_bytes);
        report.field_bounds_setup_seconds += run.report.field_bounds_setup_seconds;
      }
      stats.collapses += run.report.collapses;
      live -= run.removed;
      slot.tets = piece.mesh.tets.size();
      save_piece(scratch.piece_path(slot.file), piece);
      next.push_back(slot);
      ++stats.pieces;
      result.scratch_peak_bytes = std::max(result.scratch_peak_bytes, folder_bytes(scratch.path()));
    }
    stats.vertices_after = live;
    stats.seconds = since(level_start);
    say("level " + std::to_string(level) + ": " + std::to_string(stats.pieces) + " pieces simplified (largest " +
        std::to_string(stats.largest_piece_tets) + " tets), " + std::to_string(live) + " vertices, tolerance " +
        std::to_string(stats.tolerance) + ", " + std::to_string(stats.seconds) + " s");
    result.levels.push_back(stats);
    slots = std::move(next);
    if (slots.size() == 1 || finishing) break;
  }

  const auto write_start = Clock::now();
  result.output_pieces = static_cast<std::uint32_t>(slots.size());
  std::uint64_t out_tets = 0;
  if (slots.size() == 1) {
    Piece piece = load_piece(scratch.piece_path(slots[0].file));
    out_tets = piece.mesh.tets.size();
    write_mesh(output, piece.mesh);
    if (map) map->record_output_piece(piece.global_ids);
  } else {
    for (const PieceSlot& s : slots) out_tets += s.tets;
    write_pieces(output, scratch, slots, holders.size(), cut, map ? &*map : nullptr);
  }
  // holders[g] != 0: used by a tet (a merge takes a holder from a border vertex, never the last).
  if (map) map->write(ooc.vertex_map_path, holders);
  result.write_seconds = since(write_start);
  if (spool) {
    const auto hierarchy_start = Clock::now();
    spool->write(ooc.hierarchy_path, cut.counts.vertex_stride);
    result.hierarchy_collapses = spool->collapses();
    result.hierarchy_bytes = spool->bytes_written();
    result.hierarchy_write_seconds = since(hierarchy_start);
  }
  if (sampling) {
    // The largest bound over the output's tets: over the pieces' (each piece's are its tets').
    report.field_bounds = true;
    report.field_bound.assign(sampling->range.size(), 0.0);
    for (const PieceSlot& s : slots) raise_to(report.field_bound, s.field_bound);
    report.field_bound_rel = 0.0;
    for (std::size_t c = 0; c < report.field_bound.size(); ++c)
      report.field_bound_rel = std::max(report.field_bound_rel, report.field_bound[c] / sampling->range[c]);
  }
  report.vertices_after = live;
  report.tets_after = out_tets;
  report.status = live <= target ? Status::kOk : Status::kStoppedEarly;
  if (report.status == Status::kStoppedEarly)
    report.message = "stopped at " + std::to_string(live) + " vertices (target " + std::to_string(target) + ")" +
                     (slots.size() > 1 ? ": the memory limit kept " + std::to_string(slots.size()) + " pieces apart (" +
                                             std::to_string(result.levels.back().seams) +
                                             (result.levels.back().seams == 1 ? " seam" : " seams") +
                                             " between them; borders without one frozen)"
                                       : ": no legal collapse left");
  report.seconds = since(start);
  result.peak_rss_bytes = peak_resident_bytes();
  return result;
}

void remove_out_of_core_scratch() noexcept { ooc::remove_scratch_folders(); }

std::uint64_t parse_memory_size(const std::string& text) {
  std::size_t used = 0;
  double value = 0.0;
  try {
    value = std::stod(text, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  std::string unit = text.substr(used);
  for (char& c : unit) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  if (!unit.empty() && unit.back() == 'B') unit.pop_back();
  if (unit.size() == 2 && unit[1] == 'I') unit.pop_back();  // "GiB"
  double scale = 1.0;
  if (unit == "K") scale = 1024.0;
  else if (unit == "M") scale = 1024.0 * 1024;
  else if (unit == "G") scale = 1024.0 * 1024 * 1024;
  else if (unit == "T") scale = 1024.0 * 1024 * 1024 * 1024;
  else if (!unit.empty()) used = 0;
  if (used == 0 || !(value > 0.0) || !std::isfinite(value * scale) || value * scale > 9e18)
    throw InputError("memory size '" + text + "': expected a positive number with an optional unit K, M, G or T (e.g. 2G, 256M)");
  return static_cast<std::uint64_t>(value * scale);
}

}  // namespace topotet
