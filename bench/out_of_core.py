#!/usr/bin/env python3
"""Out of core against in core (issue #25): the same generated cube-sphere simplified both ways.

For each size N (tets) and memory limit L:
  1. `topotet generate cube-sphere --tets N -o WORK/cs_N.mesh` (streams: its peak is reported too);
  2. in core:     `topotet simplify IN -o WORK/ic_N.mesh --ratio R --no-metrics` (skipped with --no-in-core,
     or when N is above --in-core-max);
  3. out of core: `topotet simplify IN -o WORK/ooc_N_L.mesh --ratio R --memory-limit L`;
  4. `topotet check IN OUT --json` on each output (--fast above 2M tets: Euler characteristics and
     components, no distances), which also gives the field RMS and the dihedral spread.
Every command runs under `/usr/bin/time -v` (peak RSS, wall time). Printed as a table and written as
JSON (--json). Medians over --runs runs for the times (one check per output: the outputs are identical
run to run, by determinism).

    python3 bench/out_of_core.py build/cli/topotet --work /tmp/ooc --sizes 5000000 --limits 256M
    python3 bench/out_of_core.py build/cli/topotet --work /big --sizes 50000000 --limits 2G --runs 1
"""
import argparse
import json
import os
import re
import statistics
import subprocess
import sys


def timed(cmd):
    """Runs cmd under /usr/bin/time -v: (wall seconds, peak RSS bytes, stdout, stderr, exit code)."""
    p = subprocess.run(["/usr/bin/time", "-v"] + cmd, capture_output=True, text=True)
    wall = re.search(r"Elapsed \(wall clock\) time .*: (?:(\d+):)?(\d+):([\d.]+)", p.stderr)
    seconds = 0.0
    if wall:
        h, m, s = wall.groups()
        seconds = int(h or 0) * 3600 + int(m) * 60 + float(s)
    rss = re.search(r"Maximum resident set size \(kbytes\): (\d+)", p.stderr)
    return seconds, int(rss.group(1)) * 1024 if rss else 0, p.stdout, p.stderr, p.returncode


def check(topotet, inp, out, work, tag, fast):
    js = os.path.join(work, f"check_{tag}.json")
    cmd = [topotet, "check", inp, out, "--json", js, "-q"] + (["--fast"] if fast else [])
    seconds, rss, _, err, code = timed(cmd)
    with open(js) as f:
        j = json.load(f)
    q = j["after"]["quality"]
    row = {"topology": j["topology"], "check_seconds": seconds, "check_peak_bytes": rss,
           "dihedral_std_rad": q["dihedral_deg"]["std_dev"] * 3.141592653589793 / 180 if "dihedral_deg" in q else None,
           "min_mean_ratio": q.get("mean_ratio", {}).get("min")}
    if "field_error" in j:
        row["field_rms_rel"] = j["field_error"]["rms_rel"]
    if "surface_distance" in j:
        row["hausdorff_diag"] = j["surface_distance"]["hausdorff"] / j["surface_distance"]["diagonal"]
    return row


def parse_report(text):
    row = {}
    m = re.search(r"vertices\s+([\d,]+) -> ([\d,]+)", text)
    if m:
        row["vertices_before"] = int(m.group(1).replace(",", ""))
        row["vertices_after"] = int(m.group(2).replace(",", ""))
    m = re.search(r"pieces\s+(\d+) .*?, (\d+) left", text)
    if m:
        row["pieces"], row["output_pieces"] = int(m.group(1)), int(m.group(2))
    m = re.search(r"([\d,]+) collapses/s", text)
    if m:
        row["collapses_per_s"] = int(m.group(1).replace(",", ""))
    return row


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("topotet")
    ap.add_argument("--work", default="/tmp/topotet_ooc")
    ap.add_argument("--sizes", default="5000000")
    ap.add_argument("--limits", default="256M")
    ap.add_argument("--ratio", type=float, default=0.05)
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--threads", type=int, default=0)
    ap.add_argument("--no-in-core", action="store_true")
    ap.add_argument("--in-core-max", type=int, default=60_000_000)
    ap.add_argument("--json", default=None)
    a = ap.parse_args()
    os.makedirs(a.work, exist_ok=True)
    topotet = os.path.abspath(a.topotet)
    threads = ["--threads", str(a.threads)] if a.threads else []
    rows = []
    for n in [int(s) for s in a.sizes.split(",")]:
        inp = os.path.join(a.work, f"cs_{n}.mesh")
        if not os.path.exists(inp):
            s, rss, _, err, code = timed([topotet, "generate", "cube-sphere", "--tets", str(n), "-o", inp, "-q"])
            if code:
                sys.exit(err)
            print(f"generate {n}: {s:.1f} s, peak {rss / 2**20:.0f} MiB", flush=True)
        fast = n > 2_000_000
        variants = []
        if not a.no_in_core and n <= a.in_core_max:
            variants.append(("in core", None))
        variants += [("out of core", lim) for lim in a.limits.split(",")]
        for name, lim in variants:
            tag = f"{n}_{lim or 'ic'}"
            out = os.path.join(a.work, f"out_{tag}.mesh")
            cmd = [topotet, "simplify", inp, "-o", out, "--ratio", str(a.ratio)] + threads
            cmd += ["--memory-limit", lim] if lim else ["--no-metrics"]
            times, peaks, report = [], [], {}
            for _ in range(a.runs):
                s, rss, text, err, code = timed(cmd)
                if code:
                    sys.exit(f"{' '.join(cmd)}: exit {code}\n{err}")
                times.append(s)
                peaks.append(rss)
                report = parse_report(text)
                with open(os.path.join(a.work, f"report_{tag}.txt"), "w") as f:
                    f.write(text)
            row = {"tets": n, "mode": name, "limit": lim, "seconds_median": statistics.median(times),
                   "seconds": times, "peak_bytes_max": max(peaks), "bytes_per_tet": max(peaks) / n}
            row.update(report)
            row.update(check(topotet, inp, out, a.work, tag, fast))
            rows.append(row)
            print(json.dumps(row), flush=True)
    print()
    print(f"{'tets':>10} {'mode':<12} {'limit':>6} {'time s':>8} {'peak MiB':>9} {'B/tet':>6} {'pieces':>7} "
          f"{'field rms':>10} {'dih std':>8} {'topology':>8}")
    for r in rows:
        print(f"{r['tets']:>10} {r['mode']:<12} {r['limit'] or '-':>6} {r['seconds_median']:>8.1f} "
              f"{r['peak_bytes_max'] / 2**20:>9.0f} {r['bytes_per_tet']:>6.0f} {r.get('pieces', 1):>7} "
              f"{r.get('field_rms_rel', float('nan')):>10.4g} {r.get('dihedral_std_rad') or float('nan'):>8.3f} "
              f"{r['topology']:>8}")
    if a.json:
        with open(a.json, "w") as f:
            json.dump(rows, f, indent=1)


if __name__ == "__main__":
    main()
