#!/usr/bin/env bash
# Files as meshers write them, through the command-line tool: Gmsh meshes whose surfaces share
# faces (4.1 and 2.2 -save_all), Gmsh triangles that are no tet's face, mixed meshes (refused,
# or --tets-only). Gmsh is a Debian package that scripts/setup.sh installs; every mesh here is
# small (well under a second each).
#   usage: bash tests/cli_formats_test.sh path/to/topotet
set -euo pipefail

topotet=$(realpath "${1:?usage: cli_formats_test.sh path/to/topotet}")
work=$(mktemp -d "${TMPDIR:-/tmp}/topotet_cli_formats.XXXXXX")
trap 'rm -rf "$work"' EXIT
cd "$work"

passed=0
failed=0
pass() { passed=$((passed + 1)); echo "ok      $1"; }
fail() { failed=$((failed + 1)); echo "FAILED  $1"; }

# expect CODE NAME -- COMMAND...: runs COMMAND (stdout+stderr to NAME.out/.err), checks the code.
expect() {
  local want=$1 name=$2
  shift 3
  local got=0
  "$@" >"$name.out" 2>"$name.err" || got=$?
  if [[ $got == "$want" ]]; then
    pass "$name (exit $got)"
  else
    fail "$name: exit $got, expected $want"
    sed 's/^/        /' "$name.out" "$name.err" | tail -n 20
  fi
}

# expect_error NAME PATTERN -- COMMAND...: exit 2, one 'topotet: error:' line matching PATTERN.
expect_error() {
  local name=$1 pattern=$2
  shift 2
  expect 2 "$name" "$@"
  if [[ $(wc -l <"$name.err") == 1 ]] && grep -q "^topotet: error: .*$pattern" "$name.err"; then
    pass "$name: one error line with '$pattern'"
  else
    fail "$name: stderr is not one 'topotet: error:' line with '$pattern':"
    sed 's/^/        /' "$name.err" | head -n 10
  fi
}

# contains NAME FILE PATTERN: FILE has a line matching PATTERN.
contains() {
  if grep -q -- "$3" "$2"; then pass "$1"; else fail "$1: no '$3' in $2"; sed 's/^/        /' "$2" | head -n 10; fi
}

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
gmsh_mesh shared.geo shared22.msh -format msh22 -save_all
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
  if awk '/^Triangles/{getline n; c = n + 0; next} c > 0 {c--; split($1 " " $2 " " $3, v, " "); asort(v);
          k = v[1] " " v[2] " " v[3]; if ($4 == 10) a[k] = 1; if ($4 == 20) b[k] = 1}
          END {for (k in b) if (!(k in a)) exit 1}' "shared${v}_out.mesh"; then
    pass "shared$v: the cut keeps both refs on every face"
  else
    fail "shared$v: a ref-20 face lost ref 10"
  fi
  expect 0 "shared$v: check" -- "$topotet" check "shared${v}_in.mesh" "shared${v}_out.mesh"
  expect 0 "shared$v: msh out" -- "$topotet" simplify "shared$v.msh" -o "shared${v}_out.msh" --ratio 0.3
done

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

leftovers=$(find . -name '*.tmp*' | sort)
if [[ -z $leftovers ]]; then pass "no temporary files"; else fail "temporary files left: $leftovers"; fi

echo "$passed passed, $failed failed"
[[ $failed == 0 ]]
