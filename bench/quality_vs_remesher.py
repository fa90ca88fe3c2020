#!/usr/bin/env python3
"""topotet beside a remesher (issue #26 item 4): CGAL's tetrahedral_isotropic_remeshing as a
coarsener at the same output vertex count.

For every input and ratio (10% and 2%): `topotet simplify IN -o OUT --ratio R --threads 2` with the
defaults, then bench/cgal's `cgal_remesh` asked for the vertex count topotet reached. Both outputs
go through `topotet check IN OUT --json` (one quality code for both: min dihedral, tets under 10
degrees, mean of the mean ratio, and the topology verdict). Prints a markdown table, writes JSON.

    python3 bench/quality_vs_remesher.py BUILD_DIR CGAL_BIN_DIR --work /tmp/qvr [--only 'slab|seg']

BUILD_DIR holds cli/topotet; CGAL_BIN_DIR holds cgal_remesh and cgal_segmentation (a tree
configured with -DTOPOTET_BENCH_CGAL=ON: build-cgal/bench/cgal). One run of each (not medians).
Inputs the remesher cannot handle are skipped with the reason in the table.
"""
import argparse
import json
import os
import re
import subprocess
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from inputs import FAMILIES, family, shared  # noqa: E402


def run(cmd, timeout=None, check=True):
    started = time.monotonic()
    p = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=timeout)
    seconds = time.monotonic() - started
    if check and p.returncode != 0:
        raise RuntimeError(f"{' '.join(cmd)}: exit {p.returncode}\n{p.stdout[-2000:]}")
    return p, seconds


def wanted(args, name):
    return not ((args.only and not re.search(args.only, name)) or (args.skip and re.search(args.skip, name)))


def inputs(args):
    """(name, path) of the inputs --only/--skip keep; families and the segmentation made on demand."""
    out = []
    for name in FAMILIES:
        label = f"{name} {args.tets // 1000}k"
        if wanted(args, label):
            out.append((label, family(args.topotet, args.work, name, args.tets)))
    for rel in ("mfem/nested_cubes.msh", "mmg/tinyBoxt.mesh", "mmg/torus.mesh", "simnibs/sphere3.msh",
                "palace/circular_hole.msh", "palace/parallel_plate.msh", "palace/sheet_w_two_holes.msh",
                "large/liver_1.31M.mesh.gz"):
        path = shared(rel)
        if path and wanted(args, rel.split(".")[0]):
            out.append((rel.split(".")[0], path))
    label = "CGAL segmentation (ours)"
    if wanted(args, label):
        seg = args.segmentation or os.path.join(args.work, "cgal_segmentation.mesh")
        if not os.path.exists(seg):
            run([os.path.join(args.cgal, "cgal_segmentation"), "-o", seg])
        out.append((label, seg))
    return out


def check(args, src, out, tag):
    """`topotet check SRC OUT --json`: the verdict and OUT's quality."""
    j = os.path.join(args.work, f"check_{tag}.json")
    p, _ = run([args.topotet, "check", src, out, "--json", j, "-q"], check=False)
    if p.returncode not in (0, 1):
        raise RuntimeError(f"topotet check {src} {out}: exit {p.returncode}\n{p.stdout[-2000:]}")
    with open(j) as f:
        c = json.load(f)
    q = c["after"]["quality"]
    return {
        "vertices": c["after"]["vertices"],
        "tets": c["after"]["tets"],
        "min_dihedral": q["dihedral_deg"]["min"],
        "under10": q["tets_under_10_deg"],
        "under10_pct": 100.0 * q["tets_under_10_deg"] / max(1, q["tets"]),
        "mean_ratio": q["mean_ratio"]["mean"],
        "min_mean_ratio": q["min_mean_ratio"],
        "inverted": q["inverted_tets"],
        "topology": c["topology"].upper(),
        "hausdorff_rel": c["surface_distance"]["hausdorff_rel"],
        "differences": c.get("topology_differences", [])[:6],
    }


def medit_copy(args, name, path):
    """A plain MEDIT copy for cgal_remesh (which reads ASCII .mesh only)."""
    if path.endswith(".mesh"):
        return path
    out = os.path.join(args.work, re.sub(r"[^A-Za-z0-9_.-]", "_", name) + ".mesh")
    if not os.path.exists(out):
        run([args.topotet, "convert", path, out, "-q"])
    return out


def input_quality(args, name, path):
    tag = re.sub(r"[^A-Za-z0-9_.-]", "_", name) + "_in"
    return check(args, path, path, tag)


def begin(args, print_table):
    """The start both benches share: with --table-from, print that results JSON's table and return False
    (nothing runs); else resolve args.topotet from args.build, make the work folder, return True."""
    if args.table_from:
        with open(args.table_from) as f:
            print_table(json.load(f))
        return False
    args.topotet = args.build if os.path.isfile(args.build) else os.path.join(args.build, "cli", "topotet")
    os.makedirs(args.work, exist_ok=True)
    return True


def announced_input_quality(args, name, path):
    """input_quality, and a line on stderr that says which input starts."""
    inq = input_quality(args, name, path)
    print(f"## {name}: {inq['vertices']} vertices, {inq['tets']} tets, min dihedral {inq['min_dihedral']:.2f}, "
          f"under 10: {inq['under10']}", file=sys.stderr)
    return inq


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("build", help="topotet build folder (holds cli/topotet) or the topotet binary")
    ap.add_argument("cgal", help="folder of cgal_remesh and cgal_segmentation")
    ap.add_argument("--work", default="/tmp/quality_vs_remesher")
    ap.add_argument("--tets", type=int, default=100000, help="size of the generated families")
    ap.add_argument("--ratios", default="0.1,0.02")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--only", help="regex on the input names")
    ap.add_argument("--skip", help="regex on the input names to leave out")
    ap.add_argument("--segmentation", help="the CGAL segmentation (default: made by cgal_segmentation into --work)")
    ap.add_argument("--max-cgal-tets", type=int, default=1500000,
                    help="skip the remesher above this many input tets (a run must stay under ~5 min)")
    ap.add_argument("--cgal-timeout", type=float, default=900.0, help="seconds for one cgal_remesh call (its search)")
    ap.add_argument("--cgal-max-runs", type=int, default=4, help="cgal_remesh --max-runs (remeshing runs of the search)")
    ap.add_argument("--json", default=None, help="results (default WORK/quality_vs_remesher.json)")
    ap.add_argument("--table-from", help="print the table of a results JSON written earlier, run nothing")
    args = ap.parse_args()
    if not begin(args, print_table):
        return
    ratios = [float(r) for r in args.ratios.split(",")]
    results = []
    for name, path in inputs(args):
        inq = announced_input_quality(args, name, path)
        for ratio in ratios:
            tag = re.sub(r"[^A-Za-z0-9_.-]", "_", f"{name}_{ratio}")
            row = {"input": name, "path": path, "ratio": ratio, "input_quality": inq}
            # topotet, defaults.
            out_t = os.path.join(args.work, f"{tag}_topotet.mesh")
            rep = os.path.join(args.work, f"{tag}_topotet.json")
            _, wall = run([args.topotet, "simplify", path, "-o", out_t, "--ratio", str(ratio), "--threads",
                           str(args.threads), "--json", rep, "-q"])
            with open(rep) as f:
                level = json.load(f)["levels"][0]
            t = check(args, path, out_t, tag + "_topotet")
            t["seconds"] = level["simplify_seconds"]
            t["wall_seconds"] = wall
            row["topotet"] = t
            # CGAL at topotet's vertex count.
            if inq["tets"] > args.max_cgal_tets:
                row["cgal"] = {"skipped": f"{inq['tets']} tets: over --max-cgal-tets {args.max_cgal_tets} "
                                          f"(a remeshing run would exceed the time box)"}
            else:
                src = medit_copy(args, name, path)
                out_c = os.path.join(args.work, f"{tag}_cgal.mesh")
                cj = os.path.join(args.work, f"{tag}_cgal.json")
                try:
                    p, wall = run([os.path.join(args.cgal, "cgal_remesh"), src, out_c, "--vertices",
                                   str(t["vertices"]), "--json", cj, "--max-runs", str(args.cgal_max_runs)], timeout=args.cgal_timeout, check=False)
                    if p.returncode < 0:
                        runs = [l for l in p.stdout.splitlines() if l.startswith("run ")]
                        where = f" during {runs[-1].strip()}" if runs else ""
                        row["cgal"] = {"skipped": f"cgal_remesh crashed (signal {-p.returncode}){where}"}
                    elif p.returncode != 0:
                        errors = [l for l in p.stdout.splitlines() if l.startswith("cgal_remesh:")]
                        last = errors[-1:] or [l for l in p.stdout.strip().splitlines() if l][-1:] or ["(no output)"]
                        row["cgal"] = {"skipped": f"cgal_remesh failed (exit {p.returncode}): {last[0]}"}
                    else:
                        with open(cj) as f:
                            cg = json.load(f)
                        c = check(args, path, out_c, tag + "_cgal")
                        c["seconds"] = cg["chosen"]["seconds"]
                        c["search_seconds"] = cg["total_seconds"]
                        c["runs"] = len(cg["runs"])
                        c["edge_length"] = cg["chosen"]["edge_length"]
                        c["notes"] = cg.get("warnings", [])
                        row["cgal"] = c
                except subprocess.TimeoutExpired:
                    row["cgal"] = {"skipped": f"cgal_remesh over {args.cgal_timeout:.0f} s"}
            results.append(row)
            print(json.dumps(row), file=sys.stderr)
    with open(args.json or os.path.join(args.work, "quality_vs_remesher.json"), "w") as f:
        json.dump(results, f, indent=1)
    print_table(results)


def print_table(results):
    print("| input | ratio | tool | vertices | min dihedral | tets < 10 deg | mean ratio (mean) | Hausdorff / diag | time s | topology |")
    print("| --- | ---: | --- | ---: | ---: | ---: | ---: | ---: | ---: | --- |")
    for r in results:
        inq = r["input_quality"]
        for tool in ("topotet", "cgal"):
            x = r[tool]
            label = "topotet" if tool == "topotet" else "CGAL remesh"
            if "skipped" in x:
                print(f"| {r['input']} | {r['ratio']:g} | {label} | - | - | - | - | - | - | skipped: {x['skipped']} |")
                continue
            time_s = f"{x['seconds']:.2f}"
            if tool == "cgal":
                time_s += f" ({x['search_seconds']:.0f} search, {x['runs']} runs)"
            # None: a label of IN is missing in OUT, so no distance (the verdict says which).
            hausdorff = "-" if x["hausdorff_rel"] is None else f"{100 * x['hausdorff_rel']:.2f}%"
            verdict = x["topology"]
            if verdict == "FAIL" and x["differences"]:
                verdict += ": " + "; ".join(x["differences"][:2]).replace("|", "/")[:160]
            print(f"| {r['input']} ({inq['vertices']} v, min {inq['min_dihedral']:.1f} deg) | {r['ratio']:g} | {label} | "
                  f"{x['vertices']:,} | {x['min_dihedral']:.2f} | {x['under10']:,} ({x['under10_pct']:.1f}%) | "
                  f"{x['mean_ratio']:.3f} | {hausdorff} | {time_s} | {verdict} |")


if __name__ == "__main__":
    main()
