#!/usr/bin/env bash
# The VTK formats through the command-line tool (built with the VTK component, io/vtk/): a .vtu
# from topotet's own writer simplified into Exodus II and checked against it, the Exodus output
# read back and converted, a .vtu from standard input, --material-array, and the errors (each one
# line naming the file, nothing from VTK).
#   usage: bash tests/cli_vtk_test.sh path/to/topotet
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)

topotet=$(realpath "${1:?usage: cli_vtk_test.sh path/to/topotet}")
work=$(mktemp -d "${TMPDIR:-/tmp}/topotet_cli_vtk.XXXXXX")
trap 'rm -rf "$work"' EXIT
cd "$work"

source "$here/cli_harness.sh"

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
contains() {
  if grep -q -- "$3" "$2"; then pass "$1"; else fail "$1: no '$3' in $2"; sed 's/^/        /' "$2" | head -n 10; fi
}
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
