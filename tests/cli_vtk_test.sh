#!/usr/bin/env bash
# The VTK formats through the command-line tool (built with the VTK component, io/vtk/): a .vtu
# from topotet's own writer simplified into Exodus II and checked against it, the Exodus output
# read back and converted, a .vtu from standard input, --material-array, cell data carried through
# simplify (--extensive), and the errors (each one line naming the file, nothing from VTK).
#   usage: bash tests/cli_vtk_test.sh path/to/topotet
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)

topotet=$(realpath "${1:?usage: cli_vtk_test.sh path/to/topotet}")
work=$(mktemp -d "${TMPDIR:-/tmp}/topotet_cli_vtk.XXXXXX")
trap 'rm -rf "$work"' EXIT
cd "$work"

source "$here/cli_harness.sh"

quiet_stderr() {
  if [[ ! -s $2.err ]]; then pass "$1: nothing on stderr"; else fail "$1: stderr:"; sed 's/^/        /' "$2.err" | head; fi
}

# --- in.vtu (with its _substructures.vtp) -> simplify -> out.exo -> check ---
expect 0 generate -- "$topotet" generate linked-tori --tets 40000 -o in.mesh -q
expect 0 to_vtu -- "$topotet" convert in.mesh in.vtu
[[ -s in_substructures.vtp ]] && pass "in_substructures.vtp written" || fail "no in_substructures.vtp"
expect 0 info_vtu -- "$topotet" info in.vtu
quiet_stderr info_vtu info_vtu
expect 0 simplify_exo -- "$topotet" simplify in.vtu -o out.exo --ratio 0.3 --threads 2
contains "simplify: topology PASS" simplify_exo.out '^topology *PASS'
expect 0 check_exo -- "$topotet" check in.vtu out.exo
contains "check in.vtu out.exo: PASS" check_exo.out '^topology *PASS'
expect 0 check_mesh_exo -- "$topotet" check in.mesh out.exo
expect 0 info_exo -- "$topotet" info out.exo
contains "out.exo has the listed triangles" info_exo.out '^triangles .*ref 1'
contains "out.exo has the listed edges" info_exo.out '^edges .*ref 1'
contains "out.exo has the field" info_exo.out '^fields *1 (f: 1 component)'
expect 0 exo_to_vtu -- "$topotet" convert out.exo back.vtu
expect 0 check_back -- "$topotet" check out.exo back.vtu

# --- .vtu from standard input; --material-array ---
expect 0 stdin_vtu -- bash -c "\"$topotet\" info - --format vtu < in.vtu"
contains "stdin: the tets" stdin_vtu.out '^tets'
expect 0 material_array -- "$topotet" info in.vtu --material-array material
expect_error material_array_missing "no cell array 'zone' (--material-array)" -- "$topotet" info in.vtu --material-array zone
expect_error material_array_core "applies to the VTK formats only" -- "$topotet" info in.mesh --material-array material

# --- cell data: a .vtu with point and cell arrays in, every array out (docs/formats.md#cell-data) ---
# cells.mesh + cells.sol: the vertex field f, and per tet density = 1 + centroid x, region = the
# tet's material, mass = density * volume; the .vtu made from it has them as point / cell data.
expect 0 cells_generate -- "$topotet" generate cube-sphere --tets 20000 -o cells.mesh -q
awk '
  /^Vertices/ { getline nv; for (i = 1; i <= nv; i++) { getline; x[i] = $1; y[i] = $2; z[i] = $3 } next }
  /^Tetrahedra/ {
    getline nt; print "SolAtTetrahedra"; print nt; print "3 1 1 1"
    for (t = 1; t <= nt; t++) {
      getline; a = $1; b = $2; c = $3; d = $4
      ux = x[b]-x[a]; uy = y[b]-y[a]; uz = z[b]-z[a]; vx = x[c]-x[a]; vy = y[c]-y[a]; vz = z[c]-z[a]
      wx = x[d]-x[a]; wy = y[d]-y[a]; wz = z[d]-z[a]
      vol = (ux*(vy*wz-vz*wy) - uy*(vx*wz-vz*wx) + uz*(vx*wy-vy*wx)) / 6; if (vol < 0) vol = -vol
      density = 1 + (x[a]+x[b]+x[c]+x[d]) / 4
      printf "%.17g %d %.17g\n", density, $5, density * vol
    }
    exit
  }' cells.mesh >cells.tets
sed -i '/^End$/d' cells.sol
{ cat cells.tets; echo End; } >>cells.sol
echo "columns of SolAtTetrahedra in order: density, region [categorical], mass" >>cells.sol.fields.txt
expect 0 cells_to_vtu -- "$topotet" convert cells.mesh cells.vtu
contains "convert keeps the cell arrays" cells_to_vtu.out '1 field, 3 cell arrays'
expect 0 cells_info -- "$topotet" info cells.vtu
contains "info lists the cell arrays" cells_info.out '^cell arrays *3 (density: intensive, region: categorical, mass: intensive)'
expect 0 cells_simplify -- "$topotet" simplify cells.vtu -o cells_out.vtu --extensive mass --ratio 0.2 --threads 2 --json cells.json
contains "simplify reports the cell data" cells_simplify.out '^cell data *3 arrays (density: intensive, region: categorical, mass: extensive), remapped'
contains "simplify: topology PASS" cells_simplify.out '^topology *PASS'
contains "the JSON report has the remap" cells.json '"cell_remap"'
expect 0 cells_out_info -- "$topotet" info cells_out.vtu
contains "the output has the point field" cells_out_info.out '^fields *1 (f: 1 component)'
contains "the output has the cell arrays" cells_out_info.out '^cell arrays *3 (density: intensive, region: categorical, mass: intensive)'
# Through MEDIT, the values can be read: the mass is conserved, the region is the material.
expect 0 cells_to_mesh -- "$topotet" convert cells_out.vtu cells_out.mesh
# The values of SolAtTetrahedra, one line per tet (blank lines skipped), after its count and types.
mass_sum() { awk '/^SolAtTetrahedra/ { getline n; getline; for (i = 0; i < n; i++) { getline; if (NF == 0) { i--; continue } s += $3 } } END { printf "%.15g", s }' "$1"; }
in_mass=$(mass_sum cells.sol) out_mass=$(mass_sum cells_out.sol)
if awk -v a="$in_mass" -v b="$out_mass" 'BEGIN { d = a - b; if (d < 0) d = -d; exit !(d <= 1e-9 * a) }'; then
  pass "extensive mass conserved ($in_mass -> $out_mass)"
else
  fail "extensive mass not conserved: $in_mass -> $out_mass"
fi
mismatched=$(awk '/^Tetrahedra/ { getline n; for (i = 1; i <= n; i++) { getline; m[i] = $5 } }
  FILENAME ~ /sol$/ && /^SolAtTetrahedra/ { getline n; getline; for (i = 1; i <= n; i++) { getline; if (NF == 0) { i--; continue } if ($2 != m[i]) bad++ } }
  END { print bad + 0 }' cells_out.mesh cells_out.sol)
[[ $mismatched == 0 ]] && pass "region = material on every output tet" || fail "$mismatched output tets with region != material"
expect_error cells_unknown "--extensive pressure: the input has no cell array of that name" -- \
  "$topotet" simplify cells.vtu -o x.vtu --extensive pressure

# --- errors: one line naming the file, nothing from VTK ---
expect_error missing "missing.vtu: no such file" -- "$topotet" info missing.vtu
head -c 2000 in.vtu >cut.vtu
expect_error cut_vtu "cut.vtu: incomplete VTK XML file" -- "$topotet" simplify cut.vtu -o x.mesh
echo "not exodus" >bad.exo
expect_error bad_exo "bad.exo: not an Exodus II file" -- "$topotet" info bad.exo
echo "not cgns" >bad.cgns
expect_error bad_cgns "bad.cgns: not a CGNS file" -- "$topotet" check bad.cgns out.exo
expect_error write_vtk "out.vtk: writing .vtk is not supported" -- "$topotet" convert in.mesh out.vtk
expect_error format_exo "'exo' is not a format" -- "$topotet" simplify in.vtu -o - --format exo

echo "$passed passed, $failed failed"
[[ $failed == 0 ]]
