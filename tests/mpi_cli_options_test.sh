#!/usr/bin/env bash
# `topotet-mpi simplify` takes the options of `topotet simplify` from the same definitions
# (cli/simplify_options.h): this checks it on the two tools' --help and on runs.
#   - every option name of `topotet simplify --help` is in `topotet-mpi simplify --help`, and the
#     MPI tool adds exactly its own three (--partitioned, --max-passes, --count-shares);
#   - every help line of `topotet simplify` is in topotet-mpi's, word for word, or extended by a
#     "[topotet-mpi: ...]" note (the positional IN aside: it also takes partitioned Gmsh meshes);
#   - each option topotet-mpi cannot honour says so in its help and, when given, stops every rank
#     with one error line naming it and exit code 2;
#   - the same bad value gets the same message from both tools, and options new to topotet-mpi
#     (--json, -v, --field-weight, --tolerance 0) reach the run.
#   bash tests/mpi_cli_options_test.sh TOPOTET_MPI TOPOTET MPIEXEC
set -euo pipefail
topotet_mpi=$(realpath "$1")
topotet=$(realpath "$2")
mpiexec=$3
source "$(dirname "${BASH_SOURCE[0]}")/cli_harness.sh"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
mpi() { "$mpiexec" -np "$1" --oversubscribe --bind-to none "$topotet_mpi" "${@:2}"; }

expect 0 simplify_help -- "$topotet" simplify --help
expect 0 mpi_help -- mpi 1 simplify --help
# The option names: the first word of each option line, split at its commas (-o,--output).
option_names() { grep -oE '^  -[^ ]+' "$1" | tr -d ' ' | tr ',' '\n' | sort -u; }
option_names simplify_help.out >simplify.names
option_names mpi_help.out >mpi.names
if [[ $(wc -l <simplify.names) -ge 30 ]]; then pass "simplify --help lists its options"; else fail "simplify --help lists its options"; fi
missing=$(comm -23 simplify.names mpi.names)
if [[ -z $missing ]]; then pass "topotet-mpi has every option of simplify"; else fail "topotet-mpi lacks: $missing"; fi
extra=$(comm -13 simplify.names mpi.names | tr '\n' ' ')
if [[ $extra == "--count-shares --max-passes --partitioned " ]]; then
  pass "topotet-mpi adds only its own options"
else
  fail "topotet-mpi's own options: $extra"
fi

# Help texts: each line of simplify's options block, after the positional IN.
differing=0
compared=0
while IFS= read -r line; do
  compared=$((compared + 1))
  if ! grep -qF -- "$line" mpi_help.out; then
    differing=$((differing + 1))
    echo "        not in topotet-mpi's help: $line"
  fi
done < <(sed -n '/^Options:/,$p' simplify_help.out | sed 's/ *$//' | grep -v '^$')
if [[ $differing == 0 && $compared -ge 30 ]]; then pass "the same help texts ($compared lines)"; else fail "$differing of $compared help lines differ"; fi

# The options topotet-mpi cannot honour: explained in the help, refused when given.
expect 0 generate -- "$topotet" generate cube-sphere --tets 3000 -o in.mesh
for given in "--max-field-error 0.1" "--max-field-error-rel 0.1" "--field-bounds" "--feature-ref 7" \
             "--levels 0.5,0.2" "--hierarchy h.tth" "--progress lines" "--progress-interval 2"; do
  option=${given%% *}
  if grep -A1 -- "^  $option" mpi_help.out | grep -q "topotet-mpi: not available: "; then
    pass "$option: the help says why it is not available"
  else
    fail "$option: the help says why it is not available"
  fi
  # shellcheck disable=SC2086  # the option and its value are two words
  expect 2 "refused$option" -- mpi 2 simplify in.mesh -o never.mesh $given
  if [[ $(grep -c "^topotet-mpi: error: $option: not available under MPI: " "refused$option.err") == 1 && ! -e never.mesh ]]; then
    pass "$option: one error line, no output"
  else
    fail "$option: one error line, no output"
  fi
done
expect 2 refused_stdin -- mpi 1 simplify - --format mesh -o never.mesh
if grep -q "^topotet-mpi: error: -: stdin and stdout are not read or written under MPI" refused_stdin.err; then pass "- is refused"; else fail "- is refused"; fi

# As in topotet simplify, a typo in -o fails before any work, with the same message.
expect 2 simplify_no_folder -- "$topotet" simplify in.mesh -o nowhere/out.mesh
expect 2 mpi_no_folder -- mpi 2 simplify in.mesh -o nowhere/out.mesh
if grep -q "^topotet-mpi: error: nowhere/out.mesh: no such folder" mpi_no_folder.err &&
   grep -q "^topotet: error: nowhere/out.mesh: no such folder" simplify_no_folder.err; then
  pass "-o in a missing folder: the same message"
else
  fail "-o in a missing folder: the same message"
fi

# The same checks: a bad value gets the same message from both tools.
expect 2 simplify_bad_ratio -- "$topotet" simplify in.mesh -o never.mesh --ratio 0
expect 2 mpi_bad_ratio -- mpi 1 simplify in.mesh -o never.mesh --ratio 0
if grep -q "0 is not in (0, 1\]" mpi_bad_ratio.err && grep -q "0 is not in (0, 1\]" simplify_bad_ratio.err; then
  pass "--ratio 0: the same message"
else
  fail "--ratio 0: the same message"
fi

# Options new to topotet-mpi reach the run: --json (simplify's name for --report), -v, --tolerance 0,
# --field-weight (a field the mesh lacks is the engine's error, so the weight got there).
expect 0 new_options -- mpi 2 simplify in.mesh -o out.mesh --ratio 0.3 --count-shares --json report.json -v --tolerance 0
if grep -q '"passes"' report.json && grep -q "^options   ratio 0.3, .*no tolerance" new_options.out; then
  pass "--json, -v and --tolerance 0 under MPI"
else
  fail "--json, -v and --tolerance 0 under MPI"
fi
expect 0 check -- "$topotet" check in.mesh out.mesh
expect 2 unknown_field -- mpi 2 simplify in.mesh -o never.mesh --count-shares --field-weight nosuch=2
if grep -q "no field named 'nosuch'" unknown_field.err; then pass "--field-weight reaches the engine"; else fail "--field-weight reaches the engine"; fi

echo "$passed passed, $failed failed"
[[ $failed == 0 ]]
