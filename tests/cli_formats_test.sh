#!/usr/bin/env bash
# Files as meshers write them, through the command-line tool: Gmsh meshes whose surfaces share
# faces (4.1 and 2.2 -save_all), Gmsh triangles that are no tet's face, mixed meshes (refused,
# or --tets-only), binary MEDIT. Gmsh is a Debian package that scripts/setup.sh --tests installs; every mesh here is
# small (well under a second each).
#   usage: bash tests/cli_formats_test.sh path/to/topotet
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)

topotet=$(realpath "${1:?usage: cli_formats_test.sh path/to/topotet}")
work=$(mktemp -d "${TMPDIR:-/tmp}/topotet_cli_formats.XXXXXX")
trap 'rm -rf "$work"' EXIT
cd "$work"

# pass, fail, expect, expect_error, contains and the counters.
source "$here/cli_harness.sh"

# ref_count FILE.mesh REF: number of MEDIT triangles with that ref.
ref_count() {
  awk -v ref="$2" '/^Triangles/{getline n; c = n + 0; next} c > 0 {c--; if ($4 == ref) k++} END {print k + 0}' "$1"
}

gmsh_mesh() {  # gmsh_mesh GEO OUT [gmsh options...]
  local geo=$1 out=$2
  shift 2
  gmsh "$geo" -3 "$@" -o "$out" >"$out.log" 2>&1 || { fail "gmsh $geo"; tail -n 5 "$out.log"; }
}

# --- a face on two surfaces (Gmsh physical groups that share a model surface) ---
# Two boxes glued at z = 0.5; the cut is in the all-surfaces group 10 and in group 20.
cat >shared.geo <<'EOF'
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 1, 1, 0.5};
Box(2) = {0, 0, 0.5, 1, 1, 0.5};
Coherence;
Mesh.MeshSizeMax = 0.25;
Physical Volume(1) = {1};
Physical Volume(2) = {2};
s() = Surface{:};
Physical Surface(10) = {s()};
cut() = Surface In BoundingBox{-0.1, -0.1, 0.4, 1.1, 1.1, 0.6};
Physical Surface(20) = {cut()};
EOF
gmsh_mesh shared.geo shared41.msh -format msh41
gmsh_mesh shared.geo shared22.msh -format msh22  # one element line per physical group
for v in 41 22; do
  expect 0 "shared$v: simplify" -- "$topotet" simplify "shared$v.msh" -o "shared${v}_out.mesh" --ratio 0.3
  contains "shared$v: topology PASS" "shared$v: simplify.out" "topology  *PASS"
  expect 0 "shared$v: convert" -- "$topotet" convert "shared$v.msh" "shared${v}_in.mesh"
  in20=$(ref_count "shared${v}_in.mesh" 20)
  out20=$(ref_count "shared${v}_out.mesh" 20)
  if [[ $in20 -gt 0 && $out20 -gt 0 && $out20 -lt $in20 ]]; then
    pass "shared$v: surface 20 comes out ($in20 -> $out20 triangles)"
  else
    fail "shared$v: surface 20 has $in20 -> $out20 triangles"
  fi
  # Every ref-20 face is also a ref-10 face in the output.
  if awk 'function key(x, y, z, t) {
            if (x > y) { t = x; x = y; y = t } if (y > z) { t = y; y = z; z = t } if (x > y) { t = x; x = y; y = t }
            return x " " y " " z }
          /^Triangles/{getline n; c = n + 0; next}
          c > 0 {c--; k = key($1 + 0, $2 + 0, $3 + 0); if ($4 == 10) a[k] = 1; if ($4 == 20) b[k] = 1}
          END {for (k in b) if (!(k in a)) exit 1}' "shared${v}_out.mesh"; then
    pass "shared$v: the cut keeps both refs on every face"
  else
    fail "shared$v: a ref-20 face lost ref 10"
  fi
  expect 0 "shared$v: check" -- "$topotet" check "shared${v}_in.mesh" "shared${v}_out.mesh"
  expect 0 "shared$v: msh out" -- "$topotet" simplify "shared$v.msh" -o "shared${v}_out.msh" --ratio 0.3
done

# -save_all in MSH 2.2: every element once, refs are the model entities.
gmsh_mesh shared.geo shared_all22.msh -format msh22 -save_all
expect 0 save_all22 -- "$topotet" simplify shared_all22.msh -o save_all22_out.mesh --ratio 0.3
contains "save_all22: topology PASS" save_all22.out "topology  *PASS"

# The same face listed twice with the same ref: kept once, with a warning.
awk '/^Triangles/{print; getline n; print n + 1; getline first; print first; print first; next} {print}' \
  shared41_in.mesh >repeated.mesh
expect 0 repeated_face -- "$topotet" simplify repeated.mesh -o repeated_out.mesh
contains "repeated face: warning" repeated_face.err "topotet: warning: repeated.mesh: 1 triangle is listed again"

# --- listed triangles that are no tet's face: left out with a warning ---
# A rectangle lying on the box's bottom face but not fused with it: Gmsh meshes it on its own.
cat >detached.geo <<'EOF'
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 1, 1, 1};
Rectangle(10) = {0.2, 0.2, 0, 0.5, 0.5};
Mesh.MeshSizeMax = 0.3;
EOF
gmsh_mesh detached.geo detached.msh -format msh41 -save_all
expect 0 detached -- "$topotet" simplify detached.msh -o detached_out.mesh
contains "detached: warning" detached.err "listed triangles are not a face of any tet (first: triangle"
contains "detached: topology PASS" detached.out "topology  *PASS"

# --- mixed meshes: refused by default, --tets-only leaves the other cells out ---
cat >prisms.geo <<'EOF'
Point(1) = {0, 0, 0, 0.5}; Point(2) = {1, 0, 0, 0.5}; Point(3) = {0, 1, 0, 0.5};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 1};
Curve Loop(1) = {1, 2, 3}; Plane Surface(1) = {1};
Extrude {0, 0, 1} { Surface{1}; Layers{2}; Recombine; }
EOF
gmsh_mesh prisms.geo prisms.msh -format msh41
gmsh_mesh prisms.geo prisms22.msh -format msh22
expect_error mixed_msh41 "prisms: topotet simplifies tetrahedral meshes only" -- "$topotet" simplify prisms.msh -o never.mesh
expect_error mixed_msh22 "element [0-9]* (6-node prism): topotet simplifies" -- "$topotet" info prisms22.msh
sed '/^End/d' shared41_in.mesh >mixed.mesh
printf 'Hexahedra\n1\n1 2 3 4 5 6 7 8 3\nEnd\n' >>mixed.mesh
expect_error mixed_mesh "mixed.mesh:[0-9]*: 1 hexahedra: topotet simplifies" -- "$topotet" simplify mixed.mesh -o never.mesh
expect 0 tets_only -- "$topotet" simplify mixed.mesh -o tets_only.mesh --tets-only
contains "tets-only: warning with the count" tets_only.err "topotet: warning: mixed.mesh: --tets-only: left out 1 hexahedra"
[[ ! -e never.mesh ]] && pass "nothing written on error" || fail "never.mesh was written"

# --- Gmsh: partitioned files, physical names, MSH 2.2 output ---
gmsh shared41.msh -0 -part 2 -format msh41 -o part.msh >part.log 2>&1 || fail "gmsh -part"
expect 0 partitioned -- "$topotet" info part.msh --json part.json
expect 0 whole -- "$topotet" info shared41.msh --json whole.json
if python3 -c 'import json, sys
a, b = json.load(open("part.json"))["input"], json.load(open("whole.json"))["input"]
sys.exit(0 if a["materials"] == b["materials"] == {"1": a["materials"]["1"], "2": a["materials"]["2"]}
         and a["triangles_by_ref"] == b["triangles_by_ref"] and a["edges"] == b["edges"] else 1)'; then
  pass "partitioned: materials and refs from the physical groups"
else
  fail "partitioned: materials or refs differ"; cat part.json
fi
printf '$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$PhysicalNames\n2\n2 10 "walls"\n3 1 "bottom half"\n$EndPhysicalNames\n' >names.msh
sed -n '/^\$Entities/,$p' shared41.msh >>names.msh
expect 0 names_in_out -- "$topotet" simplify names.msh -o names_out.msh --ratio 0.5
contains "physical names kept" names_out.msh '"bottom half"'
expect 0 msh22_out -- "$topotet" convert shared41.msh shared_22.msh --msh22
contains "msh22 header" shared_22.msh '^2.2 0 8'
gmsh shared_22.msh -0 -format msh41 -o regmsh.msh >regmsh.log 2>&1 && pass "gmsh reads our 2.2" || fail "gmsh cannot read our 2.2"
expect 0 msh22_back -- "$topotet" convert shared_22.msh back22.mesh
expect 0 msh22_check -- "$topotet" check shared41_in.mesh back22.mesh
blocks=$(awk '/^\$Elements/{getline; print $1; exit}' shared41_out.msh)
entities=$(awk '/^\$Entities/{getline; print $1 + $2 + $3 + $4; exit}' shared41_out.msh)
[[ $blocks == "$entities" ]] && pass "one element block per entity ($blocks)" || fail "$blocks blocks for $entities entities"

# --- special files: FIFOs and devices written straight through, symlinks followed ---
mkfifo report.fifo
cat report.fifo >fifo_copy.json &
expect 0 fifo_report -- "$topotet" info shared41_in.mesh --json report.fifo
wait
[[ -p report.fifo ]] && pass "the FIFO is still a FIFO" || fail "the FIFO was replaced"
python3 -c 'import json; json.load(open("fifo_copy.json"))' && pass "JSON came through the FIFO" || fail "no JSON through the FIFO"
expect 0 dev_stdout -- "$topotet" info shared41_in.mesh --json /dev/stdout
contains "JSON on /dev/stdout" dev_stdout.out '"tets"'
[[ -e /dev/stdout && ! -f /dev/stdout ]] && pass "/dev/stdout not replaced" || fail "/dev/stdout replaced"
expect 0 dev_null -- "$topotet" simplify shared41_in.mesh -o /dev/null --format mesh --ratio 0.5 --report /dev/null
[[ -c /dev/null ]] && pass "/dev/null still a device" || fail "/dev/null replaced"
cp shared41_in.mesh target.mesh
ln -s target.mesh link.mesh
expect 0 symlink_out -- "$topotet" simplify shared41_in.mesh -o link.mesh --ratio 0.5
[[ -L link.mesh ]] && pass "the symlink stays a symlink" || fail "the symlink was replaced"
if ! cmp -s target.mesh shared41_in.mesh; then pass "its target was rewritten"; else fail "its target is unchanged"; fi

# --- "-": stdin and stdout ---
expect 0 stdin_info -- bash -c "\"$topotet\" info - --format mesh <shared41_in.mesh"
contains "stdin read" stdin_info.out "tets"
expect 0 stdin_stdout -- bash -c "\"$topotet\" simplify - -o - --format msh --ratio 0.5 <shared41.msh >piped.msh"
contains "mesh on stdout" piped.msh '^\$MeshFormat'
contains "report on stderr when the mesh is on stdout" stdin_stdout.err "topology  *PASS"
expect 0 piped_check -- "$topotet" info piped.msh
expect 0 report_stdout -- bash -c "\"$topotet\" simplify shared41.msh -o r.mesh --ratio 0.5 --report - >r.json"
python3 -c 'import json; json.load(open("r.json"))' && pass "--report - is JSON on stdout" || fail "--report - is not JSON"
expect_error stdin_no_format "the input format must be given" -- bash -c "\"$topotet\" info - <shared41_in.mesh"
expect_error stdout_no_format "the output format must be given" -- "$topotet" simplify shared41_in.mesh -o -

# --- SIGINT / SIGTERM: temporary files removed, exit 130 / 143 ---
# Background jobs of a script start with SIGINT ignored (and topotet leaves an ignored signal
# ignored, as nohup expects): env --default-signal gives them the default back.
"$topotet" generate cube-sphere --tets 60000 -o big.mesh >/dev/null
for sig in INT TERM; do
  want=$([[ $sig == INT ]] && echo 130 || echo 143)
  interrupted=0
  for delay in 0.2 0.5 0.9; do
    env --default-signal=INT "$topotet" simplify big.mesh -o sig_out.msh --levels 0.9,0.8,0.7,0.6,0.5 --no-metrics \
      >sig.out 2>sig.err &
    pid=$!
    sleep "$delay"
    kill -s "$sig" "$pid" 2>/dev/null || true
    code=0
    wait "$pid" || code=$?
    if [[ $code == "$want" ]]; then
      interrupted=$((interrupted + 1))
      grep -q "^topotet: error: " sig.err || fail "SIG$sig: no error line"
    elif [[ $code != 0 ]]; then
      fail "SIG$sig after ${delay}s: exit $code, expected $want"
    fi
    left=$(find . -name 'sig_out*.tmp-*')
    [[ -z $left ]] && pass "SIG$sig after ${delay}s (exit $code): no temporary file" || fail "SIG$sig left $left"
  done
  [[ $interrupted -gt 0 ]] && pass "SIG$sig interrupted $interrupted run(s) with exit $want" || fail "SIG$sig interrupted no run"
done

# --- binary MEDIT (.meshb + .solb): a Gmsh mesh through it and back is the same text, and a
# simplification of the .meshb checks against the .mesh ---
expect 0 meshb_write -- "$topotet" convert shared41_in.mesh shared41.meshb
expect 0 meshb_back -- "$topotet" convert shared41.meshb shared41_back.mesh
if cmp -s shared41_in.mesh shared41_back.mesh; then pass "meshb: .mesh -> .meshb -> .mesh is the same file"; else fail "meshb: round trip differs"; fi
expect 0 meshb_simplify -- "$topotet" simplify shared41.meshb -o shared41_out.meshb --ratio 0.5
expect 0 meshb_check -- "$topotet" check shared41_in.mesh shared41_out.meshb
head -c 40 shared41.meshb >cut.meshb
expect_error meshb_truncated "cut.meshb: byte " -- "$topotet" info cut.meshb

# --- option messages: plain, and before any file is read (no_such.mesh is never opened) ---
expect_error threads_negative "--threads: '-3' is not a whole number >= 0" -- "$topotet" simplify no_such.mesh -o x.mesh --threads -3
expect_error ratio_text "--ratio: 'abc' is not a number" -- "$topotet" simplify no_such.mesh -o x.mesh --ratio abc
expect_error ratio_zero "--ratio: 0 is not in (0, 1\\]" -- "$topotet" simplify no_such.mesh -o x.mesh --ratio 0
expect_error bad_format "--format: 'xyz' is not a format" -- "$topotet" simplify no_such.mesh -o - --format xyz

# --- the thread count reported is what runs (taskset, --threads beyond the cores) ---
if command -v taskset >/dev/null 2>&1; then
  expect 0 taskset_one -- taskset -c 0 "$topotet" simplify shared41_in.mesh -o t1.mesh --ratio 0.5 --report t1.json
  python3 -c 'import json, sys; sys.exit(0 if json.load(open("t1.json"))["options"]["threads"] == 1 else 1)' &&
    pass "taskset -c 0: 1 thread reported" || fail "taskset -c 0: not 1 thread"
fi
expect 0 many_threads -- "$topotet" simplify shared41_in.mesh -o t8.mesh --ratio 0.5 --threads 64
[[ ! -s many_threads.err ]] && pass "--threads 64: nothing on stderr" || fail "--threads 64 printed: $(head -c 200 many_threads.err)"

leftovers=$(find . -name '*.tmp*' | sort)
if [[ -z $leftovers ]]; then pass "no temporary files"; else fail "temporary files left: $leftovers"; fi

echo "$passed passed, $failed failed"
[[ $failed == 0 ]]
