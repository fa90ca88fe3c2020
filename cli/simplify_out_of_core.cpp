// topotet simplify IN -o OUT --memory-limit SIZE: the out-of-core run (topotet/out_of_core.h).
// The in-core pipeline reads IN whole, measures the output against it and reports; here IN is
// never whole in memory, so the report gives the counts, times, levels and the measured peak, and
// points at `topotet check IN OUT` for the topology verdict (--fast at large sizes), which needs
// both meshes in memory.
#include <cstdio>
#include <filesystem>

#include "common.h"
#include "simplify_options.h"
#include "topotet/error.h"
#include "topotet/out_of_core.h"
#include "topotet/threads.h"

namespace topotet::cli {

namespace {

// The report as JSON (--json): what the text gives, in numbers.
Json json_report(const SimplifyArgs& args, const OutOfCoreOptions& ooc, const OutOfCoreReport& r) {
  const Report& rep = r.report;
  Json levels = Json::array();
  for (const OutOfCoreLevel& lv : r.levels)
    levels.push_back({{"pieces", lv.pieces},
                      {"pairs_left_apart", lv.unmerged},
                      {"seams", lv.seams},
                      {"seams_declined", lv.seams_declined},
                      {"largest_piece_tets", lv.largest_piece_tets},
                      {"vertices_after", lv.vertices_after},
                      {"collapses", lv.collapses},
                      {"tolerance", lv.tolerance},
                      {"seconds", lv.seconds}});
  return Json{{"input", args.input},
              {"output", args.output},
              {"mode", "out of core"},
              {"status", rep.status == Status::kOk ? "ok" : "stopped early"},
              {"message", rep.message},
              {"vertices", {{"before", rep.vertices_before}, {"after", rep.vertices_after}}},
              {"tets", {{"before", rep.tets_before}, {"after", rep.tets_after}}},
              {"collapses", rep.collapses},
              {"pieces", {{"cut", r.pieces}, {"left", r.output_pieces}, {"tet_limit", r.piece_tet_limit}}},
              {"levels", levels},
              {"seconds", {{"total", rep.seconds}, {"cut", r.cut_seconds}, {"write", r.write_seconds}}},
              {"memory", {{"limit_bytes", ooc.memory_limit_bytes},
                          {"peak_rss_bytes", r.peak_rss_bytes},
                          {"scratch_peak_bytes", r.scratch_peak_bytes}}},
              {"tolerance", rep.tolerance},
              {"tolerance_asked", rep.tolerance_asked},
              {"min_quality_used", rep.min_quality_used},
              {"min_dihedral_used", rep.min_dihedral_used},
              {"relaxations", relaxations_json(rep)},
              {"field_bounds", rep.field_bounds ? Json{{"max_bound_rel", rep.field_bound_rel},
                                                       {"bound", rep.field_bound},
                                                       {"bytes", rep.field_bounds_bytes},
                                                       {"setup_seconds", rep.field_bounds_setup_seconds}}
                                                 : Json()},
              {"vertex_map", ooc.vertex_map_path},
              {"hierarchy", ooc.hierarchy_path.empty() ? Json()
                                                       : Json{{"path", ooc.hierarchy_path},
                                                              {"collapses", r.hierarchy_collapses},
                                                              {"bytes", r.hierarchy_bytes},
                                                              {"write_seconds", r.hierarchy_write_seconds}}},
              {"topology", "not checked: topotet check IN OUT"}};
}

}  // namespace

int run_simplify_out_of_core(const SimplifyArgs& args) {
  if (args.input == "-" || args.output == "-")
    throw InputError("--memory-limit: the input and the output must be files (the input is read twice: the mesh, "
                     "then its .sol)");
  check_output_format(args.output);
  if (args.report == "-") send_report_to_stderr();
  check_output_folder(args.report);
  OutOfCoreOptions ooc;
  if (!args.memory_limit.empty()) ooc.memory_limit_bytes = parse_memory_size(args.memory_limit);
  ooc.scratch_parent = args.scratch;
  ooc.pieces = args.pieces;
  ooc.piece_tets = args.piece_tets;
  ooc.cell_remap.extensive = args.extensive;
  ooc.cell_remap.categorical = args.categorical;
  ooc.vertex_map_path = args.vertex_map;
  if (!ooc.vertex_map_path.empty()) check_output_folder(ooc.vertex_map_path);
  ooc.hierarchy_path = args.hierarchy;
  if (!ooc.hierarchy_path.empty()) {
    check_output_folder(ooc.hierarchy_path);
    if (std::filesystem::path(ooc.hierarchy_path).lexically_normal() == std::filesystem::path(args.output).lexically_normal())
      throw InputError("--hierarchy " + ooc.hierarchy_path + " is the output file too: give it another name");
  }
  if (verbosity() >= Verbosity::kVerbose) ooc.log = [](const std::string& line) { print_note(line); };
  SimplifyOptions options = engine_options(args);
  // As in core: a hierarchy records each collapse's field error bound (for `extract --max-error`);
  // a mesh without vertex fields has none to record (the run then ignores this).
  if (!ooc.hierarchy_path.empty() && !args.no_field_bounds) options.track_field_bounds = true;
  OutOfCoreReport r;
  run_with_thread_limit(options.num_threads, [&] { r = simplify_out_of_core(args.input, args.output, options, ooc); });
  const Report& rep = r.report;
  std::FILE* out = report_stream();
  if (out != nullptr) {
    std::fprintf(out, "out of core  %s -> %s\n", args.input.c_str(), args.output.c_str());
    std::fprintf(out, "vertices     %s -> %s (%.1f%%)\n", format_count(rep.vertices_before).c_str(),
                 format_count(rep.vertices_after).c_str(),
                 rep.vertices_before ? 100.0 * static_cast<double>(rep.vertices_after) / static_cast<double>(rep.vertices_before) : 0.0);
    std::fprintf(out, "tets         %s -> %s\n", format_count(rep.tets_before).c_str(), format_count(rep.tets_after).c_str());
    std::fprintf(out, "pieces       %u (at most %s tets each), %u left at the end\n", r.pieces,
                 format_count(r.piece_tet_limit).c_str(), r.output_pieces);
    for (std::size_t l = 0; l < r.levels.size(); ++l) {
      const OutOfCoreLevel& lv = r.levels[l];
      std::string apart;
      if (lv.unmerged) apart += ", " + std::to_string(lv.unmerged) + (lv.unmerged == 1 ? " pair" : " pairs") + " left apart";
      if (lv.seams) apart += ", " + std::to_string(lv.seams) + (lv.seams == 1 ? " seam" : " seams") + " between pieces";
      if (lv.seams_declined) apart += " (" + std::to_string(lv.seams_declined) + " borders without: no seam fits or frees more than it freezes)";
      std::fprintf(out, "  level %zu    %u piece%s run (largest %s tets)%s, tolerance %s, %s vertices after, %s\n", l,
                   lv.pieces, lv.pieces == 1 ? "" : "s", format_count(lv.largest_piece_tets).c_str(), apart.c_str(),
                   format_number(lv.tolerance).c_str(), format_count(lv.vertices_after).c_str(),
                   format_seconds(lv.seconds).c_str());
    }
    const double simplify_seconds = rep.seconds - r.cut_seconds - r.write_seconds;
    std::fprintf(out, "time         %s (cut %s, simplify %s, write %s), %s collapses/s\n",
                 format_seconds(rep.seconds).c_str(), format_seconds(r.cut_seconds).c_str(),
                 format_seconds(simplify_seconds).c_str(), format_seconds(r.write_seconds).c_str(),
                 format_count(static_cast<std::uint64_t>(rep.collapses / std::max(rep.seconds, 1e-9))).c_str());
    std::fprintf(out, "memory       peak %s (%.0f bytes/input tet)%s; scratch folder peak %s\n",
                 format_bytes(r.peak_rss_bytes).c_str(),
                 rep.tets_before ? static_cast<double>(r.peak_rss_bytes) / static_cast<double>(rep.tets_before) : 0.0,
                 ooc.memory_limit_bytes ? (", limit " + format_bytes(ooc.memory_limit_bytes)).c_str() : "",
                 format_bytes(r.scratch_peak_bytes).c_str());
    std::fprintf(out, "tolerance    %s (mesh units), shared by the levels\n", format_number(rep.tolerance).c_str());
    if (!rep.relaxations.empty())  // by the last level's run (the whole mesh), as in core
      std::fprintf(out, "relaxed      %s, in the last level's run (the whole mesh), to reach the target; the output holds "
                   "its guarantees with these values\n", relaxations_text(rep).c_str());
    if (rep.field_bounds) {
      // The bound holds at every input vertex, as in core (engine/guarantees/field_bounds.h).
      std::string per_component;
      for (std::size_t c = 0; c < rep.field_bound.size(); ++c)
        per_component += (c ? ", " : "") + format_number(rep.field_bound[c]);
      std::fprintf(out, "field bound  %s of the range at most, at every input vertex (per component, field units: %s)%s\n",
                   format_number(rep.field_bound_rel).c_str(), per_component.c_str(),
                   rep.rejected_by(RejectReason::kFieldError) > 0
                       ? ("; the limit refused " + format_count(rep.rejected_by(RejectReason::kFieldError)) + " collapses").c_str()
                       : "");
    }
    std::fprintf(out, "topology     not checked in this run (the input is never whole in memory): topotet check %s %s%s\n",
                 args.input.c_str(), args.output.c_str(), rep.tets_before > 2'000'000 ? " --fast" : "");
    if (!ooc.vertex_map_path.empty())
      std::fprintf(out, "vertex map   %s: every input vertex -> its output vertex\n", ooc.vertex_map_path.c_str());
    if (!ooc.hierarchy_path.empty())
      std::fprintf(out, "hierarchy    %s: %s collapses, %s (written in %s); levels: topotet extract %s\n",
                   ooc.hierarchy_path.c_str(), format_count(r.hierarchy_collapses).c_str(),
                   format_bytes(r.hierarchy_bytes).c_str(), format_seconds(r.hierarchy_write_seconds).c_str(),
                   ooc.hierarchy_path.c_str());
    if (rep.status != Status::kOk) std::fprintf(out, "status       %s\n", rep.message.c_str());
  }
  if (!args.report.empty()) write_json_atomically(args.report, json_report(args, ooc, r));
  if (ooc.memory_limit_bytes != 0 && r.peak_rss_bytes > ooc.memory_limit_bytes)
    print_warning(args.output, "the peak memory " + format_bytes(r.peak_rss_bytes) + " went over the limit " +
                                   format_bytes(ooc.memory_limit_bytes));
  return kExitOk;
}

}  // namespace topotet::cli
