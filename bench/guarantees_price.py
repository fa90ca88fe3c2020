#!/usr/bin/env python3
"""The price of the guarantees (docs/performance.md "Every guarantee on"): every input simplified by
the CLI with its defaults (tolerance 0.4% of the diagonal, features at 45 degrees, at the scale of
the tolerance) and with the guarantees off (--tolerance 0 --feature-angle 180), on 1 and 2
threads, REPEAT times, the two configurations interleaved so that the drift of a shared machine
hits both. Prints one markdown row per input (medians) and writes the runs as JSON lines.

  python3 bench/guarantees_price.py build/cli/topotet [--repeat 3] [--only REGEX] [--work DIR]
      [--json FILE] [--threads 1,2]

Columns: collapses/s (simplification time of the report, so reading and writing are out), the
price (median over the repetitions of defaults time / off time, taken pairwise on one thread),
2t/1t of the defaults, rounds, peak bytes per input tet (whole process), kernel evaluations and
legality checks per collapse, and the vertex ratio reached (a run the tolerance stops early does
less work than the off run: compare collapses/s there, not times).
"""
import argparse, json, os, re, statistics, subprocess, sys

from inputs import SHARED as data, family, gmsh_multimaterial

INPUTS = [  # name, file (generated: family name), ratio
    ("cube-sphere 1M", "cube-sphere", 0.1),
    ("slab 1M", "slab", 0.1),
    ("polycrystal 1M", "polycrystal", 0.1),
    ("Gmsh 20 materials 1.13M", "gmsh:multimaterial", 0.1),
    ("liver 1.31M", f"{data}/large/liver_1.31M.mesh.gz", 0.1),
    ("LOX 513k", f"{data}/volume/lox_post_tets.mesh.gz", 0.02),
    ("tinyBoxt 63k (Mmg, 2 materials)", f"{data}/mmg/tinyBoxt.mesh", 0.1),
    ("sphere3 23k (Gmsh, 3 shells)", f"{data}/simnibs/sphere3.msh", 0.1),
]
OFF = ["--tolerance", "0", "--feature-angle", "180"]


def run(topotet, mesh, ratio, threads, extra, work):
    out = subprocess.run([topotet, "simplify", mesh, "-o", os.path.join(work, "out.mesh"), "--ratio", str(ratio),
                          "--threads", str(threads), "--no-metrics", "--json", "-"] + extra,
                         capture_output=True, text=True, check=True)
    r = json.loads(out.stdout)
    l = r["levels"][-1]
    c = max(l["collapses"], 1)
    return {"seconds": l["simplify_seconds"], "rate": l["collapses_per_second"], "rounds": l["rounds"],
            "bytes_per_tet": r["peak_rss_bytes_per_input_tet"], "evals": l["evaluations_per_collapse"],
            "checks": l["legality_checks"] / c, "reached": l["vertices_after"] / l["vertices_before"]}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("topotet")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--only", default="")
    ap.add_argument("--work", default="/tmp/topotet_price")
    ap.add_argument("--json", default="")
    ap.add_argument("--threads", default="1,2")
    a = ap.parse_args()
    os.makedirs(a.work, exist_ok=True)
    threads = [int(t) for t in a.threads.split(",")]
    sink = open(a.json, "w") if a.json else None
    print("| input | defaults 1t | defaults 2t | off 1t | off 2t | price (1t) | 2t/1t defaults | rounds (def / off) "
          "| bytes/tet (def / off) | evals/collapse | checks/collapse | reached (def / off) |")
    print("| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |")
    for name, source, ratio in INPUTS:
        if a.only and not re.search(a.only, name):
            continue
        if source == "gmsh:multimaterial":
            mesh = gmsh_multimaterial(a.work) or "gmsh (not installed)"
        else:
            mesh = source if "/" in source else family(a.topotet, a.work, source, 1000000)
        if not os.path.exists(mesh):
            print(f"skipping {name}: {mesh} not found", file=sys.stderr)
            continue
        runs = {}
        for _ in range(a.repeat):
            for t in threads:
                for cfg, extra in (("def", []), ("off", OFF)):
                    r = run(a.topotet, mesh, ratio, t, extra, a.work)
                    runs.setdefault((cfg, t), []).append(r)
                    if sink:
                        sink.write(json.dumps({"input": name, "config": cfg, "threads": t, **r}) + "\n")
                        sink.flush()
        med = lambda cfg, t, k: statistics.median(r[k] for r in runs[(cfg, t)])
        t1, t2 = threads[0], threads[-1]
        price = statistics.median(d["seconds"] / o["seconds"] for d, o in zip(runs[("def", t1)], runs[("off", t1)]))
        speedup = med("def", t1, "seconds") / med("def", t2, "seconds")
        print(f"| {name} | {med('def', t1, 'rate') / 1e3:.1f}k/s | {med('def', t2, 'rate') / 1e3:.1f}k/s "
              f"| {med('off', t1, 'rate') / 1e3:.1f}k/s | {med('off', t2, 'rate') / 1e3:.1f}k/s | {price:.2f}x "
              f"| {speedup:.2f} | {runs[('def', t1)][0]['rounds']} / {runs[('off', t1)][0]['rounds']} "
              f"| {med('def', t1, 'bytes_per_tet'):.0f} / {med('off', t1, 'bytes_per_tet'):.0f} "
              f"| {runs[('def', t1)][0]['evals']:.1f} | {runs[('def', t1)][0]['checks']:.2f} "
              f"| {runs[('def', t1)][0]['reached']:.3f} / {runs[('off', t1)][0]['reached']:.3f} |", flush=True)


if __name__ == "__main__":
    main()
