#!/usr/bin/env bash
# Smoke test of topotet-mpi: a generated mesh simplified over 2 ranks passes `topotet check`
# against its input, the report says what the passes did, a --partitioned output (.pvtu + one
# .vtu per rank) holds the same mesh as the gathered one, a mesh partitioned by gmsh (split and
# one-file forms) simplifies to the input's topology, and bad input stops every rank with one
# clear error line and exit code 2.
#   bash tests/mpi_cli_test.sh TOPOTET_MPI TOPOTET MPIEXEC
set -euo pipefail
topotet_mpi=$(realpath "$1")
topotet=$(realpath "$2")
mpiexec=$3
check_pvtu=$(realpath "$(dirname "${BASH_SOURCE[0]}")/mpi_pvtu_check.py")
source "$(dirname "${BASH_SOURCE[0]}")/cli_harness.sh"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"

expect 0 generate -- "$topotet" generate cube-sphere --tets 4000 -o in.mesh
expect 0 simplify_2_ranks -- "$mpiexec" -np 2 --oversubscribe --bind-to none "$topotet_mpi" simplify in.mesh -o out.mesh --ratio 0.2 --report report.json
expect 0 check -- "$topotet" check in.mesh out.mesh
if grep -q '"passes"' report.json && grep -q '"migrated_tets"' report.json; then pass "report lists the passes"; else fail "report lists the passes"; fi

# --partitioned: one .vtu per rank and a .pvtu; the pieces add up to the gathered result of the
# same run (the output does not depend on how it is written). These runs test input and output:
# --count-shares saves them the trial runs (the library tests cover the shares).
for ranks in 2 4; do
  expect 0 gathered_$ranks -- "$mpiexec" -np $ranks --oversubscribe --bind-to none "$topotet_mpi" simplify in.mesh -o gathered$ranks.mesh --ratio 0.2 --count-shares --quiet
  expect 0 partitioned_$ranks -- "$mpiexec" -np $ranks --oversubscribe --bind-to none "$topotet_mpi" simplify in.mesh -o parts$ranks.pvtu --ratio 0.2 --count-shares --partitioned --quiet
  expect 0 pvtu_pieces_$ranks -- python3 "$check_pvtu" parts$ranks.pvtu gathered$ranks.mesh $ranks
done
expect 2 partitioned_not_pvtu -- "$mpiexec" -np 2 --oversubscribe --bind-to none "$topotet_mpi" simplify in.mesh -o parts.mesh --partitioned
if [[ $(grep -c 'topotet-mpi: error: parts.mesh: --partitioned writes a .pvtu' partitioned_not_pvtu.err) == 1 ]]; then pass "--partitioned needs a .pvtu"; else fail "--partitioned needs a .pvtu"; fi

# Partitioned Gmsh input (Debian's gmsh, installed by scripts/setup.sh --tests): gmsh cuts the mesh in 2,
# into two files (-part_split) and into one; both simplify on 2 ranks to the input's topology.
if command -v gmsh >/dev/null; then
  expect 0 to_msh -- "$topotet" convert in.mesh whole.msh
  expect 0 gmsh_split -- gmsh whole.msh -part 2 -part_split -save -o split.msh
  expect 0 gmsh_one_file -- gmsh whole.msh -part 2 -save -o onefile.msh
  for form in split onefile; do
    expect 0 ${form}_2_ranks -- "$mpiexec" -np 2 --oversubscribe --bind-to none "$topotet_mpi" simplify $form.msh -o from_$form.mesh --ratio 0.2 --count-shares --quiet
    expect 0 ${form}_check -- "$topotet" check whole.msh from_$form.mesh
  done
  expect 2 one_piece_of_split -- "$mpiexec" -np 2 --oversubscribe --bind-to none "$topotet_mpi" simplify split_1.msh -o never.mesh
  if grep -q 'error: split_1.msh: partition 2 of 2 has no tets here' one_piece_of_split.err; then
    pass "a piece of a split mesh is not taken for the whole"
  else
    fail "a piece of a split mesh is not taken for the whole"
  fi
  expect 2 parts_vs_ranks -- "$mpiexec" -np 3 --oversubscribe --bind-to none "$topotet_mpi" simplify split.msh -o never.mesh
  if [[ $(grep -c 'error: split_1.msh: partitioned in 2 parts (gmsh -part 2), but 3 ranks run' parts_vs_ranks.err) == 1 ]]; then
    pass "parts must match ranks"
  else
    fail "parts must match ranks"
  fi
else
  fail "gmsh not found (scripts/setup.sh --tests installs it): partitioned Gmsh input untested"
fi

# Cell arrays from a whole input file: remapped on rank 0 onto the gathered output, as topotet
# simplify does (an intensive array constant per material stays that constant to rounding, a label follows the
# materials, an extensive sum is conserved); not with --partitioned (an error if asked, a warning if not).
python3 - <<'PY'
mesh = open("in.mesh").read().split()
i = mesh.index("Tetrahedra")
n = int(mesh[i + 1])
mats = [int(mesh[i + 2 + 5 * t + 4]) for t in range(n)]
rows = ["%r %r %r" % (1.0 + t % 5, 2.5 * m, 10.0 * m) for t, m in enumerate(mats)]
open("cells.sol", "w").write("MeshVersionFormatted 2\n\nDimension 3\n\nSolAtTetrahedra\n%d\n3 1 1 1\n\n" % n + "\n".join(rows) + "\n\nEnd\n")
open("cells.mesh", "w").write(open("in.mesh").read())
open("cells.sol.fields.txt", "w").write("columns of SolAtVertices in order:\ncolumns of SolAtTetrahedra in order: mass, density, label\n")
PY
expect 0 cells_2_ranks -- "$mpiexec" -np 2 --oversubscribe --bind-to none "$topotet_mpi" simplify cells.mesh -o cells_out.mesh --ratio 0.2 --extensive mass --categorical label --report cells.json
if python3 - <<'PY'
import json, sys
def tets(path):
    m = open(path).read().split()
    i = m.index("Tetrahedra")
    return [int(m[i + 2 + 5 * t + 4]) for t in range(int(m[i + 1]))]
def columns(path):
    s = open(path).read().split()
    i = s.index("SolAtTetrahedra")
    n, k = int(s[i + 1]), int(s[i + 2])
    v = [float(x) for x in s[i + 3 + k:i + 3 + k + n * k]]
    return [v[c::k] for c in range(k)]
mats = tets("cells_out.mesh")
mass0 = sum(columns("cells.sol")[0])
mass, density, label = columns("cells_out.sol")
problems = []
if len(mats) != len(mass) or len(mats) < 100:
    problems.append(f"{len(mats)} tets, {len(mass)} values")
if abs(sum(mass) - mass0) > 1e-9 * mass0:
    problems.append(f"mass {mass0} -> {sum(mass)}")
problems += [f"tet {t}: density {d} for material {m}" for t, (d, m) in enumerate(zip(density, mats)) if abs(d - 2.5 * m) > 1e-12 * m][:3]
problems += [f"tet {t}: label {l} for material {m}" for t, (l, m) in enumerate(zip(label, mats)) if l != 10.0 * m][:3]
kinds = [(a["name"], a["kind"]) for a in json.load(open("cells.json"))["cell_arrays"]]
if kinds != [("mass", "extensive"), ("density", "intensive"), ("label", "categorical")]:
    problems.append(f"report's cell_arrays {kinds}")
sys.exit("; ".join(problems) if problems else 0)
PY
then pass "cell arrays carried by topotet-mpi (constant, labels, conserved sum)"; else fail "cell arrays carried by topotet-mpi"; fi
expect 0 cells_check -- "$topotet" check cells.mesh cells_out.mesh
expect 2 cells_partitioned_extensive -- "$mpiexec" -np 2 --oversubscribe --bind-to none "$topotet_mpi" simplify cells.mesh -o cells.pvtu --partitioned --extensive mass
if grep -q 'error: --extensive / --categorical: the cell arrays are carried onto a gathered output only' cells_partitioned_extensive.err; then
  pass "--extensive with --partitioned is refused"; else fail "--extensive with --partitioned is refused"; fi
expect 0 cells_partitioned -- "$mpiexec" -np 2 --oversubscribe --bind-to none "$topotet_mpi" simplify cells.mesh -o cells.pvtu --partitioned --ratio 0.2 --count-shares --quiet
if [[ $(grep -c 'warning: cells.mesh: 3 cell arrays are not carried: with --partitioned' cells_partitioned.err) == 1 ]]; then
  pass "--partitioned warns once that the cell arrays are not carried"; else fail "--partitioned cell-array warning"; fi
expect 2 cells_unknown_name -- "$mpiexec" -np 2 --oversubscribe --bind-to none "$topotet_mpi" simplify cells.mesh -o never.mesh --extensive nope
if [[ $(grep -c "error: --extensive nope: the input has no cell array of that name (its cell arrays: 'mass', 'density', 'label')" cells_unknown_name.err) == 1 ]]; then
  pass "an unknown --extensive name is one clear error"; else fail "an unknown --extensive name is one clear error"; fi

expect 2 missing_input -- "$mpiexec" -np 2 --oversubscribe --bind-to none "$topotet_mpi" simplify nowhere.mesh -o never.mesh
if [[ $(grep -c 'topotet-mpi: error: .*nowhere.mesh' missing_input.err) == 1 ]]; then pass "one error line naming the file"; else fail "one error line naming the file"; fi

echo "$passed passed, $failed failed"
[[ $failed == 0 ]]
