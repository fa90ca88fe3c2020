#!/usr/bin/env bash
# Smoke test of topotet-mpi: a generated mesh simplified over 2 ranks passes `topotet check`
# against its input, the report says what the passes did, and bad input stops every rank with
# one clear error line and exit code 2.
#   bash tests/mpi_cli_test.sh TOPOTET_MPI TOPOTET MPIEXEC
set -euo pipefail
topotet_mpi=$(realpath "$1")
topotet=$(realpath "$2")
mpiexec=$3
source "$(dirname "${BASH_SOURCE[0]}")/cli_harness.sh"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"

expect 0 generate -- "$topotet" generate cube-sphere --tets 4000 -o in.mesh
expect 0 simplify_2_ranks -- "$mpiexec" -np 2 --oversubscribe --bind-to none "$topotet_mpi" simplify in.mesh -o out.mesh --ratio 0.2 --report report.json
expect 0 check -- "$topotet" check in.mesh out.mesh
if grep -q '"passes"' report.json && grep -q '"migrated_tets"' report.json; then pass "report lists the passes"; else fail "report lists the passes"; fi

expect 2 missing_input -- "$mpiexec" -np 2 --oversubscribe --bind-to none "$topotet_mpi" simplify nowhere.mesh -o never.mesh
if [[ $(grep -c 'topotet-mpi: error: .*nowhere.mesh' missing_input.err) == 1 ]]; then pass "one error line naming the file"; else fail "one error line naming the file"; fi

echo "$passed passed, $failed failed"
[[ $failed == 0 ]]
