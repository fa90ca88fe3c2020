#!/usr/bin/env bash
# Strong and weak scaling of topotet-mpi on 1-4 ranks (oversubscribed beyond the cores), and the
# quality of the distributed result against the shared-memory engine at the same target.
#   bash bench/mpi_scaling.sh [BUILD_DIR] [STRONG_TETS] [WEAK_TETS_PER_RANK] [THREADS_PER_RANK]
# Writes one JSON line per run (bench/mpi_bench) to mpi_scaling.jsonl in the current folder and
# prints the Markdown tables of docs/performance.md "Distributed (MPI)". Timings on a shared machine are
# noisy: run it niced on a quiet machine, and compare medians of several runs.
set -euo pipefail
build=${1:-build}
strong_tets=${2:-200000}
weak_tets=${3:-50000}
threads=${4:-1}
bench=$(realpath "$build/bench/mpi_bench")
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_mpi_yield_when_idle=1
out=mpi_scaling.jsonl
if [[ ${MPI_SCALING_TABLES_ONLY:-0} != 1 ]]; then  # 1: only print the tables of an earlier run
: >"$out"
run() {  # KIND RANKS TETS [--compare]
  local kind=$1 ranks=$2 tets=$3
  shift 3
  /usr/bin/time -f '%M' -o rss.txt nice -n 19 mpirun -np "$ranks" --oversubscribe --bind-to none \
    "$bench" cube-sphere "$tets" 0.1 "$threads" "$@" | sed "s/^{/{\"kind\":\"$kind\",/" >>"$out"
}
for ranks in 1 2 3 4; do run strong "$ranks" "$strong_tets"; done
for ranks in 1 2 3 4; do run weak "$ranks" $((weak_tets * ranks)); done
run quality 4 "$strong_tets" --compare
fi

python3 - "$out" <<'PY'
import json, sys
rows = [json.loads(l) for l in open(sys.argv[1])]
def mb(x): return f"{x / 1e6:.0f}"
for kind in ("strong", "weak"):
    print(f"\n{kind} scaling (cube-sphere, ratio 0.1)\n")
    print("| ranks | tets in | passes | simplify s (per pass) | of which trial runs s | distribute s | migrated tets (per pass) | MB sent (per pass) | peak RSS MB per rank |")
    print("|---|---|---|---|---|---|---|---|---|")
    for r in (r for r in rows if r["kind"] == kind):
        p = r["passes"]
        print(f"| {r['ranks']} | {r['tets_in']:,} | {len(p)} | {r['simplify_seconds']:.2f} ({', '.join('%.2f' % x['seconds'] for x in p)}) "
              f"| {', '.join('%.2f' % x.get('trial_seconds', 0) for x in p)} | {r['distribute_seconds']:.2f} | {', '.join(format(x['migrated_tets'], ',') for x in p)} "
              f"| {', '.join('%.2f' % (x['bytes_sent'] / 1e6) for x in p)} | {', '.join(mb(x) for x in r['peak_rss_bytes_per_rank'])} |")
for r in (r for r in rows if r["kind"] == "quality"):
    m, s = r["mpi"], r["shm"]
    print(f"\nquality, {r['ranks']} ranks vs shared memory, same target ({m['vertices']:,} vertices)\n")
    print("| run | tets | dihedral std (deg) | min mean ratio | field RMS (rel) | seconds |")
    print("|---|---|---|---|---|---|")
    print(f"| shared memory | {s['tets']:,} | {s['dihedral_std_deg']:.2f} | {s['min_mean_ratio']:.3f} | {s['field_rms_rel']:.5f} | {r['shm_seconds']:.2f} |")
    print(f"| MPI, all tets | {m['tets']:,} | {m['dihedral_std_deg']:.2f} | {m['min_mean_ratio']:.3f} | {m['field_rms_rel']:.5f} | {r['simplify_seconds']:.2f} |")
    print(f"| MPI, tets touching a former border | {m['border_tets']:,} | {m['border_dihedral_std_deg']:.2f} | {m['border_min_mean_ratio']:.3f} | | |")
PY
