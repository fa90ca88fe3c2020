#!/usr/bin/env bash
# The quality/topology table of issues #4 and #5: every generated family at the given sizes,
# simplified to 10% and 2% of its vertices by both engines in one `--levels` run each, with the
# independent topology checker on every level. Prints one row per (family, size, engine, level)
# and keeps the JSON reports in OUTDIR.
#
#   bash bench/families.sh [TOPOTET_BINARY] [SIZES] [OUTDIR]
#   bash bench/families.sh build/cli/topotet 100000,1000000 /tmp/families
set -euo pipefail
topotet=${1:-build/cli/topotet}
sizes=${2:-100000}
outdir=${3:-/tmp/topotet-families}
mkdir -p "$outdir"
for size in ${sizes//,/ }; do
  for family in cube-sphere slab linked-tori polycrystal; do
    mesh="$outdir/${family}_${size}.mesh"
    "$topotet" generate "$family" --tets "$size" -o "$mesh" > /dev/null
    for engine in sequential parallel; do
      flag=(); if [[ $engine == sequential ]]; then flag=(--sequential); fi
      "$topotet" simplify "$mesh" -o "$outdir/${family}_${size}_${engine}.mesh" --levels 0.1,0.02 \
        "${flag[@]}" --quiet --report "$outdir/${family}_${size}_${engine}.json"
    done
  done
done
python3 - "$outdir" <<'PY'
import glob, json, os, sys
rows = []
for path in sorted(glob.glob(os.path.join(sys.argv[1], "*.json"))):
    name = os.path.basename(path)[:-5]
    family, size, engine = name.rsplit("_", 2)
    report = json.load(open(path))
    peak = report.get("peak_rss_bytes_per_input_tet", float("nan"))  # whole run, all levels
    for level in report["levels"]:
        q = level["quality"]
        fe = level["field_error"] or {}
        rows.append((family, int(size), engine, level["target_vertex_ratio"], level["vertices_after"],
                     level["cumulative_seconds"], level["collapses_per_second"], level["evaluations_per_collapse"],
                     peak, fe.get("rms_rel", float("nan")), q["dihedral_deg"]["std_dev"], level["topology"]))
print(f"{'family':<12}{'tets':>9} {'engine':<11}{'level':>6}{'#vert':>9}{'cum_s':>9}{'coll/s':>10}{'eval/c':>8}"
      f"{'B/tet':>7}{'rms_rel':>10}{'dih_sd':>8}  topology")
for r in sorted(rows, key=lambda r: (r[0], r[1], r[3] * -1, r[2])):
    print(f"{r[0]:<12}{r[1]:>9} {r[2]:<11}{r[3]:>6.2f}{r[4]:>9}{r[5]:>9.2f}{r[6]:>10.0f}{r[7]:>8.1f}"
          f"{r[8]:>7.0f}{r[9]:>10.4f}{r[10]:>8.2f}  {r[11]}")
PY
