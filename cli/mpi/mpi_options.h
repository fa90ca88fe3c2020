// The options of `topotet-mpi simplify`: every option of `topotet simplify` (cli/simplify_options.h,
// the same definitions and help texts) and three of its own (--partitioned, --max-passes,
// --count-shares). The options of `simplify` that topotet::mpi cannot honour stay registered, so
// that `--help` says why, and are refused with one clear error line when given.
#pragma once

#include <string>

#include <CLI/CLI.hpp>

#include "simplify_options.h"

namespace topotet::cli::mpi {

struct MpiSimplifyArgs {
  SimplifyArgs simplify;  // the options shared with `topotet simplify`
  bool partitioned = false;
  bool count_shares = false;
  int max_passes = 8;
};

// Registers the `simplify` subcommand of topotet-mpi on `app`, writing into `args`.
void add_mpi_simplify_command(CLI::App& app, MpiSimplifyArgs& args);

// After parsing: throws InputError naming the first option given that topotet-mpi cannot honour
// (or a value it cannot take, such as - for stdin), with the reason. The same on every rank.
void check_mpi_simplify_args(const CLI::App& app, const MpiSimplifyArgs& args);

}  // namespace topotet::cli::mpi
