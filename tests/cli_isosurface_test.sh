#!/usr/bin/env bash
# End-to-end test of `topotet simplify --isosurface`: two levels of the cube-sphere's field, which
# cross its materials and listed surfaces. The run passes its own topology check (the level sets are
# listed surfaces of the embedded input), the output lists them under new refs whose vertices all
# have the level's value exactly, 1 and 2 threads write the same files, and bad specs are usage
# errors (exit 2, one line).
#   usage: bash tests/cli_isosurface_test.sh path/to/topotet
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)

topotet=$(realpath "${1:?usage: cli_isosurface_test.sh path/to/topotet}")
work=$(mktemp -d "${TMPDIR:-/tmp}/topotet_cli_iso.XXXXXX")
trap 'rm -rf "$work"' EXIT
cd "$work"

source "$here/cli_harness.sh"

expect 0 generate -- "$topotet" generate cube-sphere --tets 20000 --seed 3 -o in.mesh
expect 0 simplify_iso -- "$topotet" simplify in.mesh -o iso.mesh --isosurface f=0.1,0.3 --ratio 0.3 --threads 2 --report iso.json
if grep -q '^topology  PASS' simplify_iso.out; then pass "topology PASS with the level sets"; else fail "no topology PASS"; fi
for level in 0.1 0.3; do
  if grep -q "^isosurface iso:f=$level: ref " simplify_iso.out; then pass "level $level reported"; else fail "level $level not reported"; fi
done
expect 0 simplify_iso_1thread -- "$topotet" simplify in.mesh -o iso1.mesh --isosurface f=0.1,0.3 --ratio 0.3 --threads 1
if cmp -s iso.mesh iso1.mesh && cmp -s iso.sol iso1.sol; then pass "1 and 2 threads: same output"; else fail "1 and 2 threads differ"; fi

# Every vertex of the triangles of each level's ref (the refs the report names) has the level exactly.
refs=$(sed -n 's/^isosurface iso:f=\([0-9.]*\): ref \([0-9]*\),.*/\2=\1/p' simplify_iso.out | tr '\n' ' ')
if python3 - "$refs" <<'PY'
import sys
levels = {int(r): float(v) for r, v in (x.split("=") for x in sys.argv[1].split())}
mesh = open("iso.mesh").read().split()
sol = open("iso.sol").read().split()
i = sol.index("SolAtVertices")
n = int(sol[i + 1])
values = [float(x) for x in sol[i + 4:i + 4 + n]]
t = mesh.index("Triangles")
count = int(mesh[t + 1])
seen = {r: 0 for r in levels}
for k in range(count):
    a, b, c, ref = (int(x) for x in mesh[t + 2 + 4 * k:t + 6 + 4 * k])
    if ref in levels:
        seen[ref] += 1
        for v in (a, b, c):
            if values[v - 1] != levels[ref]:
                sys.exit(f"vertex {v} of ref {ref}: {values[v - 1]!r} != {levels[ref]!r}")
if not all(seen.values()):
    sys.exit(f"a level has no triangles: {seen}")
PY
then pass "isosurface vertices have the level exactly"; else fail "isosurface vertices off the level"; fi

if python3 -c 'import json, sys
levels = json.load(open("iso.json"))["options"]["isosurfaces"]
sys.exit(0 if [(l["field"], l["value"]) for l in levels] == [("f", 0.1), ("f", 0.3)] and all(l["ref"] > 10 for l in levels) else 1)'
then pass "the JSON report lists the levels with their refs"; else fail "options.isosurfaces in the JSON report"; fi

# A cell array through the embedding and the simplification: an extensive one keeps its sum (the
# split tets share each amount by volume before the remap shares it again).
python3 - <<'PY'
mesh = open("in.mesh").read().split()
n = int(mesh[mesh.index("Tetrahedra") + 1])
sol = open("in.sol").read().rstrip()
if sol.endswith("End"):
    sol = sol[:-3].rstrip()
sol += "\n\nSolAtTetrahedra\n%d\n1 1\n\n" % n + "\n".join(str(1.0 + t % 5) for t in range(n)) + "\n\nEnd\n"
open("cells.sol", "w").write(sol)
open("cells.mesh", "w").write(open("in.mesh").read())
names = open("in.sol.fields.txt").read()
open("cells.sol.fields.txt", "w").write(names + "columns of SolAtTetrahedra in order: mass\n")
PY
expect 0 simplify_iso_cells -- "$topotet" simplify cells.mesh -o cells_out.mesh --isosurface f=0.1 --extensive mass --ratio 0.3 --threads 2
if python3 - <<'PY'
import sys
def tet_values(path):
    sol = open(path).read().split()
    i = sol.index("SolAtTetrahedra")
    n = int(sol[i + 1])
    return [float(x) for x in sol[i + 4:i + 4 + n]]
before, after = sum(tet_values("cells.sol")), sum(tet_values("cells_out.sol"))
sys.exit(0 if abs(before - after) <= 1e-9 * before else f"mass {before} -> {after}")
PY
then pass "an extensive cell array keeps its sum through the isosurface"; else fail "extensive sum changed"; fi

expect 2 bad_field -- "$topotet" simplify in.mesh -o never.mesh --isosurface nope=1
expect 2 bad_spec -- "$topotet" simplify in.mesh -o never.mesh --isosurface f
expect 2 bad_component -- "$topotet" simplify in.mesh -o never.mesh --isosurface f:1=0.5
if [[ ! -e never.mesh ]]; then pass "no output on bad input"; else fail "bad input wrote an output"; fi
echo "$passed passed, $failed failed"
[[ $failed == 0 ]]
