#!/usr/bin/env bash
# The throughput table of issue #10: for every input, the simplification alone (both engines, 1
# and 2 threads, medians of bench_simplify's interleaved repetitions) and the whole CLI run with
# the default report (medians of farm-bench runs, 2 threads).
#
#   bash bench/throughput.sh [BUILD_DIR] [OUTDIR] [REPEAT] [ONLY]
#   bash bench/throughput.sh build /tmp/throughput 3
#   bash bench/throughput.sh build /tmp/throughput 3 'slab|LOX'   # only the inputs matching ONLY
#
# Columns: collapses/s of the parallel engine on 1 thread and of the sequential one, the 2-thread
# speed-up, kernel evaluations and checks per collapse, peak bytes per input tet (simplification
# process), the whole CLI run (read, build, simplify, measure, write) and its share spent in the
# report's measurements. Inputs of ../shared/data are skipped when absent. The engine is timed
# without the geometric defaults of issue #12 (--feature-angle 180, no tolerance), as the throughput table of docs/performance.md
# table was measured; bench/default_runs.sh measures what those defaults cost.
set -euo pipefail
build=${1:-build}
outdir=${2:-/tmp/topotet-throughput}
repeat=${3:-3}
only=${4:-}
bench="$build/bench/bench_simplify"
topotet="$build/cli/topotet"
data="$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)/shared/data"
mkdir -p "$outdir"

# name | mesh file (generated when missing) | ratio
inputs=(
  "cube-sphere 1M|$outdir/cube-sphere_1000000.mesh|0.1"
  "slab 1M|$outdir/slab_1000000.mesh|0.1"
  "linked-tori 1M|$outdir/linked-tori_1000000.mesh|0.1"
  "polycrystal 1M|$outdir/polycrystal_1000000.mesh|0.1"
  "liver 1.31M|$data/large/liver_1.31M.mesh.gz|0.1"
  "LOX 513k|$data/volume/lox_post_tets.mesh.gz|0.02"
  "tinyBoxt 63k|$data/mmg/tinyBoxt.mesh|0.25"
)
for family in cube-sphere slab linked-tori polycrystal; do
  mesh="$outdir/${family}_1000000.mesh"
  [[ -f $mesh ]] || "$topotet" generate "$family" --tets 1000000 -o "$mesh" > /dev/null
done

: > "$outdir/simplify.jsonl"
: > "$outdir/cli.txt"
for entry in "${inputs[@]}"; do
  IFS='|' read -r name mesh ratio <<< "$entry"
  [[ -z $only || $name =~ $only ]] || continue
  [[ -f $mesh ]] || { echo "skipping $name: $mesh not found" >&2; continue; }
  echo "== $name" >&2
  "$bench" --dataset "$mesh" --ratio "$ratio" --threads 1,2 --repeat "$repeat" --no-quality \
    --feature-angle 180 --tolerance-rel 0 \
    | grep '^{' | sed "s|^{|{\"name\":\"$name\",|" >> "$outdir/simplify.jsonl"
  # The whole CLI run, default report; farm-bench prints min / median / max.
  wall=$(farm-bench -n "$repeat" --warmup 0 --timeout 3600 -- \
           "$topotet" simplify "$mesh" -o "$outdir/out.mesh" --ratio "$ratio" --threads 2 --report "$outdir/report.json" \
           --feature-angle 180 --tolerance 0 \
         | awk '/^A wall s/ {print $4}')
  # Every measurement of the report (quality, field error, distance, topology check of input and
  # output) and its share of the simplification, from the last run.
  share=$(python3 -c "import json; r=json.load(open('$outdir/report.json')); print(r['metrics_seconds'], r['metrics_share_of_simplify'])" | tr ' ' '|')
  echo "$name|$wall|$share" >> "$outdir/cli.txt"
done

python3 - "$outdir" <<'PY'
import collections, json, os, statistics, sys
outdir = sys.argv[1]
runs = collections.defaultdict(list)
for line in open(os.path.join(outdir, "simplify.jsonl")):
    r = json.loads(line)
    runs[(r["name"], r["engine"], r["threads"])].append(r)
cli = {}
for line in open(os.path.join(outdir, "cli.txt")):
    name, wall, measure, share = line.strip().split("|")
    cli[name] = (float(wall), float(measure), float(share))
def med(name, engine, threads, key):
    v = [r[key] for r in runs.get((name, engine, threads), [])]
    return statistics.median(v) if v else float("nan")
names = list(dict.fromkeys(k[0] for k in runs))
print("| input | collapses | par 1t s (coll./s) | seq 1t s (coll./s) | par 2t s | 2t/1t | eval/coll | checks/coll | peak B/tet | CLI run s (measurements s, share of simplification) |")
print("| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |")
for n in names:
    p1, s1, p2 = (med(n, "parallel", 1, "seconds"), med(n, "sequential", 1, "seconds"), med(n, "parallel", 2, "seconds"))
    c = med(n, "parallel", 1, "collapses")
    # The speed-up from the runs of one repetition (interleaved, so they saw the same load).
    pairs = zip(runs.get((n, "parallel", 1), []), runs.get((n, "parallel", 2), []))
    speedups = [a["seconds"] / b["seconds"] for a, b in pairs]
    speedup = statistics.median(speedups) if speedups else float("nan")
    wall, measure, share = cli.get(n, (float("nan"),) * 3)
    print(f"| {n} | {c:,.0f} | {p1:.2f} ({c / p1 / 1000:.1f}k) | {s1:.2f} ({c / s1 / 1000:.1f}k) | {p2:.2f} | {speedup:.2f} "
          f"| {med(n, 'parallel', 1, 'evaluations_per_collapse'):.1f} | {med(n, 'parallel', 1, 'checks_per_collapse'):.2f} "
          f"| {med(n, 'parallel', 2, 'peak_bytes_per_tet'):.0f} | {wall:.2f} ({measure:.2f}, {100 * share:.0f}%) |")
PY
