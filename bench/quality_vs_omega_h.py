#!/usr/bin/env python3
"""topotet beside Sandia's Omega_h (issue #50 item 3): Omega_h's metric adaptation used as a
coarsener at the same output vertex count.

For every input: `topotet simplify IN -o OUT --ratio R --threads 2` with the defaults, then
bench/omega_h's `omega_h_coarsen` (an isotropic metric, the implied one scaled, approached with
Omega_h::adapt(): coarsening, swaps, sliver removal) asked for the vertex count topotet reached,
once per thread count of --omega-threads (OMP_NUM_THREADS). Both outputs go through `topotet check
IN OUT --json` (one quality code for both: min dihedral, tets under 10 degrees, mean of the mean
ratio, Hausdorff distance of the surfaces, and the topology verdict of the mesh and of every
substructure). Prints a markdown table, writes JSON.

    python3 bench/quality_vs_omega_h.py TOPOTET OMEGA_H_BIN_DIR --work /tmp/qvo [--only 'cube|torus']

TOPOTET is a topotet build folder (holds cli/topotet) or the binary; OMEGA_H_BIN_DIR holds
omega_h_coarsen (bench/omega_h/README.md). Times: the fastest of --repeat runs (default 3; the
machine may be shared). Omega_h's time is that of the adapt() loop at the metric scale its
vertex-count search chose (the search: full runs from the input at other scales, given beside it).
"""
import argparse
import json
import os
import re
import subprocess
import sys

sys.dont_write_bytecode = True  # no __pycache__ in the checkout
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from inputs import family, shared  # noqa: E402
from quality_vs_remesher import announced_input_quality, begin, check, medit_copy, run, wanted  # noqa: E402

SHARED_INPUTS = ("mfem/nested_cubes.msh", "simnibs/sphere3.msh", "palace/parallel_plate.msh",
                 "palace/circular_hole.msh", "palace/sheet_w_two_holes.msh", "mmg/torus.mesh", "mmg/tinyBoxt.mesh")


def inputs(args):
    """(name, path) of the inputs --only/--skip keep: the generated families, then ../shared/data."""
    out = []
    for name in [f for f in args.families.split(",") if f]:
        label = f"{name} {args.tets // 1000}k"
        if wanted(args, label):
            out.append((label, family(args.topotet, args.work, name, args.tets)))
    for rel in SHARED_INPUTS:
        path = shared(rel)
        if path and wanted(args, rel.split(".")[0]):
            out.append((rel.split(".")[0], path))
    for spec in args.input:  # --input NAME=PATH: a mesh of one's own, after the others
        name, path = spec.split("=", 1)
        if wanted(args, name):
            out.append((name, path))
    return out


def omega_h(args, name, path, tag, vertices, threads):
    """omega_h_coarsen at VERTICES with THREADS OpenMP threads: its report and OUT's check, or a skip.
    The time is the fastest of --repeat runs: the search, then runs at the scale it chose."""
    src = medit_copy(args, name, path)
    out = os.path.join(args.work, f"{tag}_omega_h_t{threads}.mesh")
    rep = os.path.join(args.work, f"{tag}_omega_h_t{threads}.json")
    env = dict(os.environ, OMP_NUM_THREADS=str(threads), OMP_PROC_BIND="false")
    load = os.getloadavg()[0]  # the machine is shared: the 1-minute load before the run
    cmd = [os.path.join(args.omega_h, "omega_h_coarsen"), src, out, "--vertices", str(vertices), "--json", rep,
           "--max-tries", str(args.max_tries), "--feature-angle", str(args.feature_angle)]
    try:
        p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, env=env,
                           timeout=args.omega_timeout)
    except subprocess.TimeoutExpired:
        return {"skipped": f"omega_h_coarsen over {args.omega_timeout:.0f} s"}
    if p.returncode != 0:
        lines = [l for l in p.stdout.strip().splitlines() if l.strip()]
        what = f"signal {-p.returncode}" if p.returncode < 0 else f"exit {p.returncode}"
        return {"skipped": f"omega_h_coarsen failed ({what}): " + " / ".join(lines[-2:])[:300]}
    with open(rep) as f:
        oh = json.load(f)
    chosen = oh["tries"][oh["chosen"]]
    times = [chosen["seconds"]]
    for k in range(1, args.repeat):
        again = os.path.join(args.work, f"{tag}_omega_h_t{threads}_again.mesh")
        rj = os.path.join(args.work, f"{tag}_omega_h_t{threads}_again.json")
        subprocess.run(cmd[:2] + [again] + cmd[3:6] + [rj, "--max-tries", "1", "--scale", repr(chosen["scale"]),
                                                     "--feature-angle", str(args.feature_angle)],
                       stdout=subprocess.DEVNULL, stderr=subprocess.STDOUT, env=env, timeout=args.omega_timeout,
                       check=True)
        with open(rj) as f:
            t = json.load(f)["tries"][0]
        if t["vertices"] != chosen["vertices"]:
            raise RuntimeError(f"{again}: {t['vertices']} vertices, the search gave {chosen['vertices']} at that scale")
        times.append(t["seconds"])
    c = check(args, path, out, f"{tag}_omega_h_t{threads}")
    c.update(seconds=min(times), run_seconds=times, search_seconds=sum(t["seconds"] for t in oh["tries"]),
             tries=len(oh["tries"]), threads=oh["threads"], scale=chosen["scale"],
             min_quality_allowed=chosen["min_quality_allowed"], untagged_faces=oh["untagged_faces"],
             feature_edges=oh["feature_edges"], feature_vertices=oh["feature_vertices"],
             loop_vertices=oh["loop_vertices"], aborted_tries=sum(1 for t in oh["tries"] if t["aborted"]),
             omega_h=oh["omega_h"], load_before=load)
    return c


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("build", help="topotet build folder (holds cli/topotet) or the topotet binary")
    ap.add_argument("omega_h", help="folder of omega_h_coarsen")
    ap.add_argument("--work", default="/tmp/quality_vs_omega_h")
    ap.add_argument("--families", default="cube-sphere", help="generated families, by commas ('' = none)")
    ap.add_argument("--tets", type=int, default=200000, help="size of the generated families")
    ap.add_argument("--ratio", type=float, default=0.1)
    ap.add_argument("--threads", type=int, default=2, help="topotet --threads")
    ap.add_argument("--omega-threads", default="1,2", help="OMP_NUM_THREADS of the omega_h_coarsen runs, by commas")
    ap.add_argument("--max-tries", type=int, default=5, help="omega_h_coarsen --max-tries (vertex-count search)")
    ap.add_argument("--feature-angle", type=float, default=45.0, help="omega_h_coarsen --feature-angle (topotet's default)")
    ap.add_argument("--repeat", type=int, default=3, help="runs of each tool at the chosen settings; the fastest counts")
    ap.add_argument("--omega-timeout", type=float, default=900.0, help="seconds for one omega_h_coarsen call")
    ap.add_argument("--only", help="regex on the input names")
    ap.add_argument("--input", action="append", default=[], metavar="NAME=PATH", help="an extra input (repeatable)")
    ap.add_argument("--skip", help="regex on the input names to leave out")
    ap.add_argument("--json", default=None, help="results (default WORK/quality_vs_omega_h.json)")
    ap.add_argument("--table-from", help="print the table of a results JSON written earlier, run nothing")
    args = ap.parse_args()
    if not begin(args, print_table):
        return
    results = []
    for name, path in inputs(args):
        inq = announced_input_quality(args, name, path)
        tag = re.sub(r"[^A-Za-z0-9_.-]", "_", f"{name}_{args.ratio}")
        row = {"input": name, "path": path, "ratio": args.ratio, "input_quality": inq}
        out_t = os.path.join(args.work, f"{tag}_topotet.mesh")
        rep = os.path.join(args.work, f"{tag}_topotet.json")
        load = os.getloadavg()[0]
        times = []
        for _ in range(args.repeat):  # the same output every time; the fastest time counts
            p, wall = run([args.topotet, "simplify", path, "-o", out_t, "--ratio", str(args.ratio), "--threads",
                           str(args.threads), "--json", rep, "-q"], check=False)
            if p.returncode not in (0, 1):  # 1: the topology changed; the check below says so
                raise RuntimeError(f"topotet simplify {path}: exit {p.returncode}\n{p.stdout[-2000:]}")
            with open(rep) as f:
                level = json.load(f)["levels"][0]
            times.append(level["simplify_seconds"])
        t = check(args, path, out_t, tag + "_topotet")
        t.update(seconds=min(times), run_seconds=times, wall_seconds=wall, threads=args.threads, load_before=load)
        row["topotet"] = t
        row["omega_h"] = [dict(omega_h(args, name, path, tag, t["vertices"], int(n)), requested_threads=int(n))
                          for n in args.omega_threads.split(",")]
        results.append(row)
        print(json.dumps(row), file=sys.stderr)
    with open(args.json or os.path.join(args.work, "quality_vs_omega_h.json"), "w") as f:
        json.dump(results, f, indent=1)
    print_table(results)


def print_table(results):
    print("| mesh | tool | vertices | time s (fastest run) | min dihedral | tets < 10 deg | mean quality (mean ratio) "
          "| Hausdorff / diag | topology |")
    print("| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | --- |")
    for r in results:
        inq = r["input_quality"]
        mesh = f"{r['input']} ({inq['vertices']:,} v, {inq['tets']:,} tets, min {inq['min_dihedral']:.1f} deg)"
        rows = [("topotet", r["topotet"])] + [("Omega_h", x) for x in r["omega_h"]]
        for label, x in rows:
            threads = x.get("threads", x.get("requested_threads"))
            label = f"{label} ({threads} thr)"
            if "skipped" in x:
                print(f"| {mesh} | {label} | - | - | - | - | - | - | not run: {x['skipped'].replace('|', '/')} |")
                continue
            time_s = f"{x['seconds']:.2f}"
            if "tries" in x:
                aborted = f", {x['aborted_tries']} aborted" if x.get("aborted_tries") else ""
                time_s += f" ({x['search_seconds']:.1f} search, {x['tries']} tries{aborted})"
            hausdorff = "-" if x["hausdorff_rel"] is None else f"{100 * x['hausdorff_rel']:.2f}%"
            verdict = x["topology"]
            if verdict == "FAIL" and x["differences"]:
                verdict += ": " + "; ".join(x["differences"][:2]).replace("|", "/")[:200]
            print(f"| {mesh} | {label} | {x['vertices']:,} | {time_s} | {x['min_dihedral']:.2f} | "
                  f"{x['under10']:,} ({x['under10_pct']:.1f}%) | {x['mean_ratio']:.3f} | {hausdorff} | {verdict} |")


if __name__ == "__main__":
    main()
