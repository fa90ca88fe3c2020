#!/usr/bin/env bash
# The table of default runs (docs/performance.md "Default runs"): every family and every mesh of
# ../shared/data simplified with default options to 10% and 2%, and again with --tolerance 0 (the
# speed cost of the tolerance) and optionally with another binary (e.g. main's, before the
# defaults existed). One row per run: reached vertex ratio, whether the run stopped early with collapses refused for the tolerance,
# measured Hausdorff distance (largest over the labels, and the number of labels above H),
# simplification time, detected feature edges and corners.
#
#   bash bench/default_runs.sh build/cli/topotet [OTHER_TOPOTET] > default_runs.txt
# Environment: TETS (family size, default 200000), RATIOS (default "0.1 0.02"), THREADS (default 1),
# MESHES (default: all), WORK (scratch folder, default /tmp/topotet_default_runs), DEFAULT_ARGS
# (options added to the "default" rows), DEFAULT_ONLY=1 (skip the --tolerance 0 rows).
set -euo pipefail
topotet=$(realpath "$1")
other=${2:+$(realpath "$2")}
here=$(cd "$(dirname "$0")/.." && pwd)
data="$here/../shared/data"
tets=${TETS:-200000}
ratios=${RATIOS:-"0.1 0.02"}
threads=${THREADS:-1}
work=${WORK:-/tmp/topotet_default_runs}
mkdir -p "$work"

meshes=${MESHES:-"cube-sphere slab linked-tori polycrystal mfem/nested_cubes.msh simnibs/sphere3.msh
  palace/circular_hole.msh palace/sheet_w_two_holes.msh palace/parallel_plate.msh mmg/tinyBoxt.mesh mmg/torus.mesh
  volume/lox_post_tets.mesh.gz large/liver_1.31M.mesh.gz"}

input_of() {
  case "$1" in
    */*) echo "$data/$1" ;;
    *)
      local f="$work/$1_$tets.mesh"
      [ -f "$f" ] || nice -n 19 "$topotet" generate "$1" --tets "$tets" -o "$f" > /dev/null
      echo "$f"
      ;;
  esac
}

row() {  # mesh ratio config binary [extra options]
  local mesh=$1 ratio=$2 config=$3 bin=$4
  shift 4
  local json="$work/report.json"
  rm -f "$json"
  nice -n 19 "$bin" simplify "$(input_of "$mesh")" -o "$work/out.mesh" --ratio "$ratio" --threads "$threads" \
    --no-verify --quiet --report "$json" "$@" || true
  python3 - "$json" "$mesh" "$ratio" "$config" << 'EOF'
import json, sys
path, mesh, ratio, config = sys.argv[1:]
try:
    r = json.load(open(path))
except Exception as e:
    print(f"| {mesh} | {ratio} | {config} | failed: {e} |")
    sys.exit(0)
l = r["levels"][-1]
d = l["surface_distance"]
h = l.get("tolerance", 0.0)
diag = d["diagonal"]
labels = d["labels"]
over = sum(1 for x in labels if x["hausdorff"] is not None and h > 0 and x["hausdorff"] > h)
stopped = "yes" if l.get("tolerance_limited") else "no"
print(f"| {mesh} | {ratio} | {config} | {l['vertices_after'] / l['vertices_before']:.3f} | {stopped} | "
      f"{100 * d['hausdorff'] / diag:.3f}% | {100 * h / diag:.2f}% | {over}/{len(labels)} | "
      f"{l['simplify_seconds']:.2f} | {l.get('feature_edges', 0)} | {l.get('feature_corners', 0)} |")
EOF
}

echo "| mesh | target | options | reached | H may have stopped it | Hausdorff / diag | H / diag | labels > H | simplify s | feature edges | corners |"
echo "| --- | ---: | --- | ---: | --- | ---: | ---: | ---: | ---: | ---: | ---: |"
for mesh in $meshes; do
  for ratio in $ratios; do
    row "$mesh" "$ratio" default "$topotet" ${DEFAULT_ARGS:-}
    [ -z "${DEFAULT_ONLY:-}" ] && row "$mesh" "$ratio" "--tolerance 0" "$topotet" --tolerance 0
    [ -n "$other" ] && row "$mesh" "$ratio" "other binary" "$other"
  done
done
