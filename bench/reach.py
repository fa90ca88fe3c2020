#!/usr/bin/env python3
"""Reach with the defaults (issue #23): asked vs reached, and what holds the rest.

For every input: `topotet simplify IN -o OUT --ratio R --threads T --json J` with every other option
at its default, then one markdown row: the vertices asked and left, how many times the target that
is, the stop diagnosis's dominant reason with its share of the vertices left (`reached` when the
target was met), the pinned vertices, the tolerance H and dihedral floor that hold for the output
(the defaults relax where they would stop the run short: SimplifyOptions::relax_tolerance,
relax_quality), the measured Hausdorff distance (both relative to the diagonal), and the topology
verdict of the output against the input.

    python3 bench/reach.py build/cli/topotet                       # families 200k + ../shared/data
    python3 bench/reach.py build/cli/topotet --only 'torus|liver' --ratios 0.1
    python3 bench/reach.py build/cli/topotet --extra my_part.msh   # more inputs, by path
"""
import argparse
import json
import os
import re
import subprocess
import sys

from inputs import FAMILIES, family, shared

SHARED_MESHES = ("mfem/nested_cubes.msh", "simnibs/sphere3.msh", "palace/circular_hole.msh",
                 "palace/sheet_w_two_holes.msh", "palace/parallel_plate.msh", "mmg/tinyBoxt.mesh",
                 "mmg/torus.mesh", "volume/lox_post_tets.mesh.gz", "large/liver_1.31M.mesh.gz")


def inputs(topotet, work, tets, extra):
    out = [(f"generate {name} {tets // 1000}k", family(topotet, work, name, tets)) for name in FAMILIES]
    for rel in SHARED_MESHES:
        path = shared(rel)
        if path:
            out.append((re.sub(r"\.(msh|mesh)(\.gz)?$", "", rel), path))
    out.extend((os.path.basename(p), p) for p in extra)
    return out


def row(topotet, name, path, ratio, threads, work):
    json_path = os.path.join(work, "reach.json")
    if os.path.exists(json_path):
        os.remove(json_path)
    run = subprocess.run([topotet, "simplify", path, "-o", os.path.join(work, "reach_out.mesh"), "--ratio", str(ratio),
                          "--threads", str(threads), "--quiet", "--json", json_path],
                         stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    if run.returncode != 0 or not os.path.exists(json_path):
        return f"| {name} | {ratio:.0%} | failed: {run.stderr.strip()[:120]} | | | | | | | | |"
    report = json.load(open(json_path))
    level = report["levels"][-1]
    before, after = level["vertices_before"], level["vertices_after"]
    asked = max(1, round(ratio * before))
    stopped = level.get("stopped")
    if stopped:
        reason = f"{stopped['dominant']} {stopped['dominant_share']:.0%}"
        if stopped.get("beyond_reach"):  # the topology and the input's pins alone hold the target
            reason += ", beyond reach"
        pinned = sum(stopped["pinned_vertices"].values())
    else:
        reason, pinned = "reached", 0
    topology = level.get("topology") or report.get("topology") or "-"
    # The limits as they held (relaxed by default where they would stop the run short) and the
    # measured two-sided Hausdorff distance, both as a share of the diagonal.
    distance = level.get("surface_distance") or {}
    diagonal = distance.get("diagonal") or 0.0
    h, h_asked = level.get("tolerance", 0.0), level.get("tolerance_asked", 0.0)
    held = (f"{h / diagonal:.2%}" if diagonal and h else "off") + (f" ({h / h_asked:.0f}x)" if h_asked and h != h_asked else "")
    floor = f"{level.get('min_dihedral_used', 0.0):.3g}"
    hausdorff = f"{distance['hausdorff_rel']:.2%}" if "hausdorff_rel" in distance else "-"
    return (f"| {name} | {before:,} | {ratio:.0%} | {asked:,} | {after:,} ({after / before:.1%}) | {after / asked:.2f} | "
            f"{reason} | {pinned:,} | {held} | {floor} | {hausdorff} | {str(topology).lower()} |")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("topotet")
    parser.add_argument("--work", default="/tmp/topotet_reach")
    parser.add_argument("--tets", type=int, default=200000)
    parser.add_argument("--ratios", type=float, nargs="+", default=[0.1, 0.02])
    parser.add_argument("--threads", type=int, default=2)
    parser.add_argument("--only", help="regular expression on the input names")
    parser.add_argument("--extra", nargs="*", default=[], help="more input files")
    args = parser.parse_args()
    os.makedirs(args.work, exist_ok=True)
    topotet = os.path.abspath(args.topotet)
    print("| input | vertices | asked | target | left | x target | stopped by (share of the vertices left) | pinned | "
          "H that holds (x asked) | min dihedral used | Hausdorff | topology |")
    print("| --- | ---: | ---: | ---: | ---: | ---: | --- | ---: | ---: | ---: | ---: | --- |")
    for name, path in inputs(topotet, args.work, args.tets, args.extra):
        if args.only and not re.search(args.only, name):
            continue
        for ratio in args.ratios:
            print(row(topotet, name, path, ratio, args.threads, args.work), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
