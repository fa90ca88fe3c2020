#!/usr/bin/env bash
# Smooth multi-material meshes from a real mesher, the counterpart of the generated families (whose
# interfaces are staircases of the generator's tets): Gmsh (OpenCASCADE) meshes a ball in a cube
# (2 materials) and two linked tori in a box (5 materials), then each is simplified with the
# defaults to every ratio, with one or two binaries side by side. One row per run: vertices
# reached, status, largest Hausdorff distance over the labels (and H), min dihedral, topology.
# docs/performance.md "Reach with the defaults" quotes it.
#
#   bash bench/gmsh_smooth.sh build/cli/topotet [OTHER_TOPOTET]
# Environment: RATIOS (default "0.1 0.02"), THREADS (default 2), SIZE_BALL (default 0.03),
# SIZE_TORI (default 0.09), WORK (scratch folder, default /tmp/topotet_gmsh_smooth). Needs gmsh.
set -euo pipefail
binaries=("$(realpath "$1")")
[[ $# -gt 1 ]] && binaries+=("$(realpath "$2")")
ratios=${RATIOS:-"0.1 0.02"}
threads=${THREADS:-2}
work=${WORK:-/tmp/topotet_gmsh_smooth}
mkdir -p "$work"
cd "$work"
command -v gmsh >/dev/null || { echo "gmsh_smooth.sh: needs gmsh (apt-get install gmsh)" >&2; exit 2; }

cat >ball.geo <<GEO
SetFactory("OpenCASCADE");
Box(1) = {0, 0, 0, 1, 1, 1};
Sphere(2) = {0.5, 0.5, 0.5, 0.3};
BooleanFragments{ Volume{1}; Delete; }{ Volume{2}; Delete; }
Physical Volume("ball", 1) = {2};
Physical Volume("box", 2) = {3};
Mesh.MeshSizeMax = ${SIZE_BALL:-0.03};
Mesh.MeshSizeMin = ${SIZE_BALL:-0.03};
GEO
cat >tori.geo <<GEO
SetFactory("OpenCASCADE");
Box(1) = {-2, -2, -1.2, 4, 4, 2.4};
Torus(2) = {-0.5, 0, 0, 1, 0.3};
Torus(3) = {0.5, 0, 0, 1, 0.3, 2*Pi};
Rotate {{1,0,0},{0.5,0,0}, Pi/2} { Volume{3}; }
BooleanFragments{ Volume{1}; Delete; }{ Volume{2,3}; Delete; }
v() = Volume{:};
For i In {0:#v()-1}
  Physical Volume(i+1) = {v(i)};
EndFor
Mesh.MeshSizeMax = ${SIZE_TORI:-0.09};
GEO
for model in ball tori; do
  [[ -s $model.msh ]] || gmsh -3 $model.geo -o $model.msh -format msh41 -nt 1 >"$model.gmsh.log" 2>&1
done

printf '| mesh | tets | asked | binary | reached | status | Hausdorff / H | min dihedral | topology |\n'
printf '| --- | ---: | ---: | --- | ---: | --- | ---: | ---: | --- |\n'
for model in ball tori; do
  for r in $ratios; do
    for b in "${binaries[@]}"; do
      "$b" simplify $model.msh -o out.mesh --ratio "$r" --threads "$threads" --json run.json -q || true
      python3 - "$model" "$r" "$b" <<'PY'
import json, sys
model, ratio, binary = sys.argv[1:]
r = json.load(open("run.json"))
l = r["levels"][-1]
d = l["surface_distance"]
worst = max((x["hausdorff"] or 0.0) for x in d["labels"]) if d else float("nan")
print(f"| {model} | {l['tets_before']:,} | {float(ratio):.0%} | {binary} | {l['vertices_after'] / l['vertices_before']:.1%} "
      f"| {l['status']} | {worst:.3g} / {l['tolerance']:.3g} | {l['quality']['dihedral_deg']['min']:.2f} | {l['topology']} |")
PY
    done
  done
done
