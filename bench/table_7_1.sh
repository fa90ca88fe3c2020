#!/usr/bin/env bash
# Paper 001, table 7.1 (a) Bucky ball and (c) Liquid Oxygen Post, with an isosurface kept as an
# embedded structure (issue #24): % vertices, #vertices, field RMS, cumulative time and the standard
# deviations of the dihedral, solid and face angles at 50/30/20/10/5/2%, the paper's row beside ours,
# and the Betti numbers of the isosurface at every level (the run's own checker verifies that every
# complex, the isosurface included, keeps them).
#   usage: bench/table_7_1.sh [BUILD_DIR=build] [THREADS=2] [BUCKY_LEVEL=128] [LOX_LEVEL=0.8]
#   TABLE_ARGS="--optimize none" bench/table_7_1.sh   adds options to both runs (the paper optimises
#   nothing after its collapses; our default --optimize light costs 6.6 s of LOX's first level, 50%)
# Notes on the comparison: our Bucky.raw is the 32^3 volume (32,768 samples, 178,746 tets), not the
# paper's 331,485-vertex mesh; the paper gives neither its levels nor its RMS units (ours: relative
# to the field's range, the first field). Our percentages are of the embedded input's vertices (the
# isosurface adds one vertex per crossed edge). Times: the paper's on a 2 GHz Xeon (seconds,
# cumulative), ours cumulative over the levels, simplification only (--levels simplifies each level
# from the previous one).
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
build=$(realpath "${1:-$here/../build}")
threads=${2:-2}
bucky_level=${3:-128}
lox_level=${4:-0.8}
data=$(realpath "$here/../../shared/data/volume")
work=$(mktemp -d "${TMPDIR:-/tmp}/topotet_table_7_1.XXXXXX")
trap 'rm -rf "$work"' EXIT

"$build/bench/raw_to_mesh" "$data/Bucky.raw" "$work/bucky.mesh" density >/dev/null

run() {  # run NAME INPUT ISOSURFACE PAPER_ROWS
  local name=$1 input=$2 iso=$3 paper=$4
  "$build/cli/topotet" simplify "$input" -o "$work/$name.mesh" --isosurface "$iso" \
    --levels 0.5,0.3,0.2,0.1,0.05,0.02 --threads "$threads" --json "$work/$name.json" --progress none ${TABLE_ARGS:-} \
    >"$work/$name.out" 2>&1 || { cat "$work/$name.out"; exit 1; }
  echo "== $name, isosurface $iso, $threads threads =="
  grep '^isosurface ' "$work/$name.out"
  python3 - "$work/$name.json" "$paper" <<'PY'
import json, sys
report = json.load(open(sys.argv[1]))
paper = {int(r.split()[0]): r.split() for r in sys.argv[2].strip().split(";")}
iso_ref = report["options"]["isosurfaces"][0]["ref"]
print(f"{'%':>4} | {'paper: #vert':>12} {'rms':>6} {'time':>5} {'dihed':>6} {'solid':>6} {'face':>6} |"
      f" {'ours: #vert':>11} {'rms':>7} {'time s':>7} {'dihed':>6} {'solid':>6} {'face':>6} | iso Betti  topology")
first = report["levels"][0]
q0 = report["input"]["quality"]
p = paper[100]
print(f"{100:>4} | {p[1]:>12} {p[2]:>6} {p[3]:>5} {p[4]:>6} {p[5]:>6} {p[6]:>6} | {first['vertices_before']:>11}"
      f" {0:>7} {0:>7} {q0['std_dev_dihedral_rad']:>6.3f} {q0['std_dev_solid_sr']:>6.3f} {q0['std_dev_face_rad']:>6.3f} |")
for level in report["levels"]:
    pct = round(100 * level["target_vertex_ratio"])
    p = paper[pct]
    q = level["quality"]
    betti = level["topology_report"]["surfaces"][str(iso_ref)]["betti"]
    print(f"{pct:>4} | {p[1]:>12} {p[2]:>6} {p[3]:>5} {p[4]:>6} {p[5]:>6} {p[6]:>6} | {level['vertices_after']:>11}"
          f" {level['field_error']['rms_rel']:>7.4f} {level['cumulative_seconds']:>7.2f} {q['std_dev_dihedral_rad']:>6.3f}"
          f" {q['std_dev_solid_sr']:>6.3f} {q['std_dev_face_rad']:>6.3f} | {betti}  {level['topology']}")
PY
}

# The paper's rows: % #vert rms time dihedral solid face.
bucky_paper="100 331485 0 0 0.383 0.508 0.383;50 165742 0.016 44 0.397 0.463 0.361;30 99445 0.023 67 0.431 0.455 0.368;
20 66297 0.029 80 0.458 0.456 0.377;10 33148 0.034 94 0.477 0.461 0.383;5 16574 0.039 103 0.489 0.468 0.388;
2 6629 0.064 117 0.497 0.477 0.393"
lox_paper="100 126890 0 0 0.571 0.575 0.608;50 63445 0.039 20 0.607 0.602 0.612;30 38067 0.073 29 0.637 0.627 0.615;
20 25378 0.089 33 0.661 0.646 0.617;10 12689 0.098 39 0.676 0.658 0.619;5 6344 0.122 42 0.686 0.667 0.622;
2 2537 0.111 46 0.691 0.674 0.624"
run bucky "$work/bucky.mesh" "density=$bucky_level" "$(echo "$bucky_paper" | tr -d '\n')"
run lox "$data/lox_post_tets.mesh.gz" "Pressure=$lox_level" "$(echo "$lox_paper" | tr -d '\n')"
