#!/usr/bin/env python3
"""Quality of the output with `--optimize none|light|full` (issue #26), side by side.

For every input: `topotet simplify IN -o OUT --ratio R --threads T --optimize O --json J` with the
defaults otherwise, then a markdown table of the output's min dihedral, tets with a dihedral under
10 and 5 degrees, mean ratio (min, mean), field RMS, the simplification time and the optimisation's
share of it, and the topology verdict (every run is checked against its input).

    python3 bench/optimize_quality.py build/cli/topotet --work /tmp/oq            # families 100k + shared
    python3 bench/optimize_quality.py build/cli/topotet --only 'slab|liver' --ratio 0.02
"""
import argparse
import json
import os
import re
import subprocess
import sys

from inputs import FAMILIES, family, shared


def inputs(topotet, work, tets):
    out = [(f"{name} {tets // 1000}k", family(topotet, work, name, tets), None) for name in FAMILIES]
    for rel, ratio in (("mmg/tinyBoxt.mesh", None), ("mmg/torus.mesh", None), ("simnibs/sphere3.msh", None),
                       ("palace/circular_hole.msh", None), ("palace/parallel_plate.msh", None),
                       ("palace/sheet_w_two_holes.msh", None), ("large/liver_1.31M.mesh.gz", None),
                       ("volume/lox_post_tets.mesh.gz", 0.02)):
        path = shared(rel)
        if path:
            out.append((os.path.basename(rel).split(".")[0], path, ratio))
    return out


def run(topotet, path, ratio, threads, optimize, work):
    report = os.path.join(work, "report.json")
    out = os.path.join(work, "out.mesh")
    cmd = [topotet, "simplify", path, "-o", out, "--ratio", str(ratio), "--threads", str(threads),
           "--optimize", optimize, "--json", report]
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    with open(report) as f:
        level = json.load(f)["levels"][0]
    q = level["quality"]
    fe = level["field_error"]
    return {
        "min_dihedral": q["dihedral_deg"]["min"],
        "under10": q["tets_under_10_deg"],
        "under5": q["tets_under_5_deg"],
        "tets": q["tets"],
        "min_ratio": q["min_mean_ratio"],
        "mean_ratio": q["mean_ratio"]["mean"],
        "rms": fe["rms_rel"] if fe else None,
        "seconds": level["simplify_seconds"],
        "optimize_seconds": level.get("optimize_seconds", 0.0),
        "topology": level.get("topology", "?"),
        "vertices": level["vertices_after"],
    }


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("topotet")
    ap.add_argument("--work", default="/tmp/optimize_quality")
    ap.add_argument("--tets", type=int, default=100000, help="size of the generated families")
    ap.add_argument("--ratio", type=float, default=0.1)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--only", default="", help="regex on the input names")
    ap.add_argument("--json", default="", help="append every run as a JSON line")
    args = ap.parse_args()
    os.makedirs(args.work, exist_ok=True)
    print("| input | optimize | min dihedral | tets under 10 deg | under 5 deg | mean ratio min / mean | field RMS | "
          "simplify s (optimize share) | topology |")
    print("| --- | --- | ---: | ---: | ---: | ---: | ---: | ---: | --- |")
    for name, path, ratio in inputs(args.topotet, args.work, args.tets):
        if args.only and not re.search(args.only, name):
            continue
        for optimize in ("none", "light", "full"):
            r = run(args.topotet, path, ratio or args.ratio, args.threads, optimize, args.work)
            share = 100.0 * r["optimize_seconds"] / r["seconds"] if r["seconds"] else 0.0
            rms = f"{r['rms']:.4f}" if r["rms"] is not None else "-"
            print(f"| {name} | {optimize} | {r['min_dihedral']:.2f} | {r['under10']} ({100.0 * r['under10'] / r['tets']:.1f}%) "
                  f"| {r['under5']} | {r['min_ratio']:.3f} / {r['mean_ratio']:.3f} | {rms} | {r['seconds']:.2f} ({share:.0f}%) "
                  f"| {r['topology']} |", flush=True)
            if args.json:
                with open(args.json, "a") as f:
                    f.write(json.dumps({"input": name, "optimize": optimize, **r}) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
