#!/usr/bin/env bash
# topotet simplify --memory-limit / --pieces (out of core) through the command-line tool: a run
# passes `topotet check`; SIGINT midway leaves no scratch folder and no output; a scratch folder
# that fills up (a file-size ulimit) is one clear error and leaves nothing; options out of core
# cannot honour are refused before any work; a field error limit holds at every input vertex; a
# hierarchy file is recorded and gives levels; pieces kept apart are joined by seams. Meshes of ~100k tets at most (a few seconds).
#   usage: bash tests/cli_out_of_core_test.sh path/to/topotet
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)

topotet=$(realpath "${1:?usage: cli_out_of_core_test.sh path/to/topotet}")
work=$(mktemp -d "${TMPDIR:-/tmp}/topotet_cli_ooc.XXXXXX")
trap 'rm -rf "$work"' EXIT
cd "$work"
source "$here/cli_harness.sh"

# no_litter NAME: the folder holds nothing the run left behind (scratch folder, temporary outputs).
no_litter() {
  if ls -A | grep -q -e '^\.topotet-scratch' -e '\.tmp-'; then
    fail "$1: left $(ls -A | grep -e '^\.topotet-scratch' -e '\.tmp-' | head -n 3 | tr '\n' ' ')"
  else
    pass "$1: no scratch folder or temporary file left"
  fi
}

"$topotet" generate cube-sphere --tets 30000 -o small.mesh -q
"$topotet" generate cube-sphere --tets 400000 -o big.mesh -q

expect 0 run -- "$topotet" simplify small.mesh -o out.mesh --pieces 8 --ratio 0.2 --json run.json
if grep -q "pieces       8" run.out && grep -q "topotet check" run.out; then pass "run: report gives the pieces and the check"; else fail "run: report"; cat run.out; fi
# The JSON report: the same counts, one entry per level (level 0 and three merges of 8 pieces).
if python3 -c '
import json, sys
j = json.load(open("run.json"))
assert j["mode"] == "out of core" and j["pieces"]["cut"] == 8 and j["pieces"]["left"] == 1, j["pieces"]
assert len(j["levels"]) == 4 and j["levels"][-1]["vertices_after"] == j["vertices"]["after"], j["levels"]
assert 0 < j["vertices"]["after"] < j["vertices"]["before"] and j["memory"]["peak_rss_bytes"] > 0
' 2>run_json.err; then pass "run: --json report"; else fail "run: --json report"; cat run_json.err; fi
expect 0 check -- "$topotet" check small.mesh out.mesh
no_litter run

# --vertex-map out of core: every input vertex -> the output vertex it became, across the levels.
expect 0 vertex_map -- "$topotet" simplify small.mesh -o vm.mesh --pieces 8 --ratio 0.2 --optimize none --vertex-map vm.txt
contains vertex_map_report vertex_map.out "vertex map.*vm.txt"
expect 0 vertex_map_valid -- python3 "$here/vertex_map_check.py" vm.txt small.mesh vm.mesh
no_litter vertex_map

# A field error limit out of core: the report gives the bound, and `topotet check` measures the
# error at every input vertex within it.
expect 0 bounds -- "$topotet" simplify small.mesh -o fb.mesh --pieces 8 --ratio 0.1 --max-field-error-rel 0.005 --json fb.json
contains bounds_report bounds.out "field bound .* of the range at most, at every input vertex"
expect 0 bounds_check -- "$topotet" check small.mesh fb.mesh --json fb_check.json
if python3 -c '
import json
run, check = json.load(open("fb.json")), json.load(open("fb_check.json"))
bound, measured = run["field_bounds"]["max_bound_rel"], check["field_error"]["max_rel_at_input_vertices"]
assert 0 < measured <= bound <= 0.005, (measured, bound)
' 2>bounds_json.err; then pass "bounds: measured at the input vertices within the bound"; else fail "bounds: measured"; cat bounds_json.err; fi
no_litter bounds

# A hierarchy file out of core: recorded on disk, read by `topotet extract` (which checks the
# level's topology against the original); its coarsest level is the run's output; with a vertex
# map it is refused before any work, and a hierarchy named as the output is refused.
expect 0 hierarchy -- "$topotet" simplify small.mesh -o hy.mesh --pieces 8 --ratio 0.2 --hierarchy hy.tth --json hy.json
contains hierarchy_report hierarchy.out "hierarchy    hy.tth: .* collapses"
expect 0 hierarchy_extract -- "$topotet" extract hy.tth -o hy_half.mesh --vertices 3000
contains hierarchy_extract_check hierarchy_extract.out "topology  PASS against the original"
expect 0 hierarchy_coarsest -- "$topotet" extract hy.tth -o hy_all.mesh --vertices 1
expect 0 hierarchy_same -- "$topotet" check hy.mesh hy_all.mesh --json hy_same.json
if python3 -c '
import json
run, check = json.load(open("hy.json")), json.load(open("hy_same.json"))
assert run["hierarchy"]["collapses"] > 0 and run["hierarchy"]["path"] == "hy.tth", run["hierarchy"]
before, after = check["before"], check["after"]
assert before["vertices"] == after["vertices"] and before["tets"] == after["tets"], (before, after)
assert check["surface_distance"]["hausdorff_rel"] < 1e-12 and check["field_error"]["max_rel"] < 1e-12, check
' 2>hierarchy_json.err; then pass "hierarchy: the coarsest level is the output"; else fail "hierarchy: coarsest level"; cat hierarchy_json.err; fi
expect_error hierarchy_map "exclude" -- "$topotet" simplify small.mesh -o x.mesh --pieces 8 --hierarchy x.tth --vertex-map x.txt
expect_error hierarchy_is_output "is the output file too" -- "$topotet" simplify small.mesh -o x.mesh --pieces 8 --hierarchy x.mesh
no_litter hierarchy

# Pieces the limit keeps apart (--piece-tets: pieces of at most 9,000 tets, so the two halves at
# 30% no longer fit together): a seam joins them, the output (written from the pieces, MEDIT)
# reaches the target and passes `topotet check`; a format that needs the mesh whole is refused.
expect 0 seams -- "$topotet" simplify small.mesh -o seams.mesh --pieces 2 --piece-tets 9000 --ratio 0.3 --json seams.json
contains seams_report seams.out "1 seam between pieces"
if python3 -c '
import json
j = json.load(open("seams.json"))
last = j["levels"][-1]
assert last["pairs_left_apart"] == 1 and last["seams"] == 1, last
assert j["pieces"]["left"] >= 3, j["pieces"]
assert abs(j["vertices"]["after"] - round(0.3 * j["vertices"]["before"])) <= 0.02 * j["vertices"]["before"], j["vertices"]
' 2>seams_json.err; then pass "seams: --json gives the seam, the target is reached"; else fail "seams: --json"; cat seams_json.err; fi
expect 0 seams_check -- "$topotet" check small.mesh seams.mesh
expect_error seams_vtu "MEDIT" -- "$topotet" simplify small.mesh -o seams.vtu --pieces 2 --piece-tets 9000 --ratio 0.3
no_litter seams

# SIGINT midway: the run is killed while pieces are on disk. (Job control on: a background job of
# a non-interactive shell would otherwise start with SIGINT ignored, and topotet keeps it so.)
rm -f out.mesh out.sol
set -m
"$topotet" simplify big.mesh -o big_out.mesh --pieces 16 --ratio 0.1 --threads 1 >sigint.out 2>sigint.err &
pid=$!
set +m
for _ in $(seq 1 200); do
  if ls -A | grep -q '^\.topotet-scratch' && ls .topotet-scratch-*/piece-* >/dev/null 2>&1; then break; fi
  sleep 0.05
done
kill -INT "$pid"
code=0
wait "$pid" || code=$?
if [[ $code == 130 ]]; then pass "sigint: exit 130"; else fail "sigint: exit $code"; fi
if [[ ! -e big_out.mesh ]]; then pass "sigint: no output"; else fail "sigint: an output was left"; fi
no_litter sigint

# A scratch folder that fills up: a file-size limit (the shell's ulimit -f, in 1 KiB blocks here).
expect_error full_disk "scratch folder.*file size limit" -- bash -c "ulimit -f 2000; trap '' XFSZ; exec '$topotet' simplify big.mesh -o full.mesh --pieces 4"
[[ ! -e full.mesh ]] && pass "full_disk: no output" || fail "full_disk: an output was left"
no_litter full_disk

# A Gmsh MSH 4.1 file (Gmsh's own, without fields) streams too, and the output checks against it.
"$topotet" simplify "$here/data/gmsh_sphere_in_box.msh" -o sphere_out.mesh --ratio 0.3 --pieces 4 -q
if "$topotet" check "$here/data/gmsh_sphere_in_box.msh" sphere_out.mesh -q; then pass "msh_input: check passes"; else fail "msh_input: check fails"; fi
no_litter msh_input

# Refused before any work.
expect_error tiny_limit "memory-limit.*at least" -- "$topotet" simplify big.mesh -o x.mesh --memory-limit 4M
expect_error bad_size "memory size 'lots'" -- "$topotet" simplify big.mesh -o x.mesh --memory-limit lots
"$topotet" convert small.mesh small.msh -q
# A .msh with node and cell fields streams ($NodeData, $ElementData), and gives the output of the
# same mesh as MEDIT (as the .msh reads: its surfaces grouped by entity).
"$topotet" convert small.msh small_back.mesh -q
expect 0 msh_fields -- "$topotet" simplify small.msh -o msh_fields.mesh --pieces 4 --ratio 0.3
expect 0 mesh_fields -- "$topotet" simplify small_back.mesh -o mesh_fields.mesh --pieces 4 --ratio 0.3
if cmp -s msh_fields.mesh mesh_fields.mesh && cmp -s msh_fields.sol mesh_fields.sol; then pass "msh_fields: the same output as the .mesh"; else fail "msh_fields: differs from the .mesh's"; fi
"$topotet" convert small.mesh small.vtu -q
expect_error not_streamed "streams MEDIT .* and Gmsh MSH 4.1 .*convert it" -- "$topotet" simplify small.vtu -o x.mesh --memory-limit 1G
expect_error isosurface "excludes" -- "$topotet" simplify big.mesh -o x.mesh --memory-limit 1G --isosurface sol0=0.5
no_litter refused

echo "$passed passed, $failed failed"
[[ $failed == 0 ]]
