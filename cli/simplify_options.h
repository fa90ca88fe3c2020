// The options of `topotet simplify`, defined once for both tools that simplify a file: `topotet
// simplify` (cli/simplify.cpp) and `topotet-mpi simplify` (cli/mpi/main.cpp). Each registers them
// with add_simplify_options, so that names, checks, defaults and help texts cannot drift; the MPI
// tool then refuses the few it cannot honour (cli/mpi/mpi_options.h says which and why).
//
//   SimplifyArgs args;                               // the values as given on the command line
//   SimplifyOptionSet set = add_simplify_options(cmd, args);
//   ... parse ...
//   SimplifyOptions o = engine_options(args);        // what steers the engine
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "topotet/simplify.h"

namespace topotet::cli {

// Every option of `simplify`, as given (before the defaults that depend on the input apply).
struct SimplifyArgs {
  std::string input;
  std::string output;
  std::string format;                // --format, checked by parse_format before any reading
  std::string hierarchy;             // --hierarchy
  std::string vertex_map;            // --vertex-map
  std::vector<double> levels_error;  // --levels-error
  double ratio = 0.25;
  std::uint64_t target_vertices = 0;
  double max_cost = 0.0;
  double min_quality = SimplifyOptions{}.min_quality;
  double min_dihedral = SimplifyOptions{}.min_dihedral;
  std::string size_weight = "auto";  // --size-weight auto|W
  double tolerance = -1.0;  // < 0: not given (the relative default applies)
  double tolerance_rel = SimplifyOptions{}.tolerance_rel;
  // A limit given on the command line holds as given; the defaults relax when they would stop the
  // run before its target (SimplifyOptions::relax_tolerance, relax_quality, relax_features);
  // --hard-limits: none of them.
  bool tolerance_given = false;  // --tolerance or --tolerance-rel
  bool quality_given = false;    // --min-quality or --min-dihedral
  bool features_given = false;   // --feature-angle
  bool hard_limits = false;
  double max_field_error = 0.0;
  double max_field_error_rel = 0.0;
  bool field_bounds = false;
  std::string field_bound_mode = "vertices";  // --field-bound-mode
  bool no_field_bounds = false;  // --hierarchy without the bounds (cheaper; levels by cost)
  double feature_angle = SimplifyOptions{}.feature_angle;
  std::optional<std::int32_t> feature_ref;
  std::string optimize = to_string(SimplifyOptions{}.optimize);  // --optimize none|light|full
  bool sequential = false;
  int threads = 0;
  double round_fraction = SimplifyOptions{}.round_fraction;
  std::string report;
  bool no_verify = false;
  bool no_metrics = false;
  std::vector<double> levels;
  std::vector<std::string> field_weights;  // NAME=W, checked by field_weight_syntax
  std::vector<std::string> isosurfaces;    // FIELD=VALUE[,VALUE...], checked by parse_isosurface_spec
  std::string progress = "auto";
  double progress_interval = 10.0;
  bool binary = false;
  bool tets_only = false;
  bool msh22 = false;
  std::string material_array;  // --material-array (VTK formats)
  std::vector<std::string> extensive;    // --extensive NAME: cell arrays conserved as sums
  std::vector<std::string> categorical;  // --categorical NAME: cell arrays remapped as labels
  std::string memory_limit;  // --memory-limit SIZE: out of core (topotet/out_of_core.h) under SIZE
  std::string scratch;       // --scratch DIR: the out-of-core scratch folder's parent
  std::uint32_t pieces = 0;  // --pieces N: out of core in exactly N pieces (tests, benchmarks)
  std::uint64_t piece_tets = 0;  // --piece-tets N: out of core, pieces of at most N tets (tests, benchmarks)
};

// The registered options, for a tool that adds its own rules to some of them.
struct SimplifyOptionSet {
  CLI::Option* input = nullptr;
  CLI::Option* output = nullptr;
  // Options by their first long name ("--levels"), in the order of the help.
  std::vector<CLI::Option*> all;
  CLI::Option* find(const std::string& long_name) const;
};

// Registers every option of `simplify` on `cmd` (with -v/-q), writing into `args`, which must
// outlive the parse.
SimplifyOptionSet add_simplify_options(CLI::App* cmd, SimplifyArgs& args);

// The engine's settings the options give (targets, limits, tolerance, features, engine, threads,
// field weights, isosurface levels without their refs: run_simplify embeds them and sets the refs).
// The tolerance: --tolerance given (even 0) wins and turns the relative one off.
SimplifyOptions engine_options(const SimplifyArgs& args);

// -v: what the run was asked for, after the defaults and the thread cap ("ratio 0.2, min quality
// 0.05, ..."); `levels` as normalize_levels returns them.
std::string options_text(const SimplifyOptions& o, const std::vector<double>& levels);

}  // namespace topotet::cli
