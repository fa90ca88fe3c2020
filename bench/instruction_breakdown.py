#!/usr/bin/env python3
"""Where the instructions of one `topotet simplify` run go, per collapse, by family.

  python3 bench/instruction_breakdown.py [--topotet PATH] [--keep OUT.callgrind] [--json FILE]
      INPUT -- [simplify options...]
  python3 bench/instruction_breakdown.py --from-callgrind FILE --report REPORT.txt [--json FILE]

Runs `valgrind --tool=callgrind topotet simplify INPUT -o TMP/out.mesh --threads 1 --no-metrics
OPTIONS` (--threads 1 unless OPTIONS give --threads; the output mesh goes to a temporary folder
that is removed), reads the report topotet prints (collapses, evaluations/collapse, legality
checks, inversion refusals) and the inclusive instruction counts of `callgrind_annotate
--inclusive=yes --tree=both`, and prints one row per family of the run: k instructions per
collapse and share of the program's total. Instructions are exact and repeatable (unlike times):
compare two builds with --keep on each and --from-callgrind later. A 50k-tet input takes ~30 s
under callgrind; keep inputs small (<= 200k tets).

A family is the inclusive count of its top-level function (the largest among the functions whose
name holds its substring: the function, its lambdas and the TBB wrappers of its loops nest, so
they are not added); families with several disjoint top-level functions add them. Where a
family's top-level function is called from inside another family's (the cost model from the
Rounds constructor), it is taken out of the outer one, so the rows add up to the total; what no
family catches is "other". The rows "across phases" are inclusive counts of kernel functions
called from several phases: they overlap the rows above. --keep OUT also writes topotet's stdout
to OUT.report.txt, for --from-callgrind OUT --report OUT.report.txt.
"""
import argparse
import json
import os
import re
import shlex
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent

# The round loop of the parallel engine: Rounds::run is inlined into simplify_parallel in Release
# builds, and with it Rounds::evaluate, Rounds::verify and Rounds::threshold (their loops over
# fewer items than a grain run inline too, so some calls come straight from the loop).
ROUND_LOOP = ["Rounds::run()", "topotet::detail::simplify_parallel("]  # the first found

# name, groups (disjoint top-level functions, added; within a group the largest match is taken),
# arcs (callee substrings whose calls from the round loop itself belong to the family).
FAMILIES = [
    ("read input", [["topotet::read_mesh(", "topotet::cli::read_input(", "topotet::cli::read_mesh_file("]], []),
    ("build + reorder model",
     [["topotet::build_mesh_model(", "topotet::build_tet_mesh(", "topotet::cli::build_input("],
      ["topotet::reorder_for_locality("]], []),
    ("features", [["topotet::detect_features("], ["topotet::feature_scale("]], []),
    ("tolerance set-up (surface reference)",
     [["topotet::find_special_faces("], ["topotet::SurfaceReference::from_mesh("],
      ["topotet::SurfaceCoverage::SurfaceCoverage("]], []),
    ("cost model set-up", [["topotet::CostModel::CostModel("]], []),
    ("initial proposals", [["Rounds::Rounds("]], []),
    ("evaluate (proposals)", [["Rounds::evaluate("]],
     ["topotet::detail::Proposals::propose(", "topotet::detail::Proposals::update("]),
    ("verify (kernel on candidates)", [["Rounds::verify()"]], ["topotet::detail::Proposals::verify("]),
    ("select (threshold, stencils, reservations)", [["Rounds::select("], ["Rounds::threshold("]], []),
    ("prove (tolerance proof of winners)", [["Rounds::prove("]], []),
    ("apply (collapses + stencil updates)", [["Rounds::apply("]], []),
    ("sequential engine (--sequential)", [["topotet::detail::simplify_sequential("]], []),
    ("stall handling (relax, flips, diagnosis)",
     [["topotet::detail::relax_limits(", "topotet::detail::flip_at_stall("], ["topotet::detail::diagnose_stop("]], []),
    ("optimize pass",
     [["topotet::optimize_after_collapses("], ["topotet::InputSamples::InputSamples("],
      ["topotet::InputSamples::index("]], []),
    ("write output",
     [["topotet::write_mesh(", "topotet::cli::write_mesh_file("],
      ["topotet::detail::MeshModel::to_mesh_data(", "topotet::TetMesh::to_mesh_data("]], []),
]
SELECT = "select (threshold, stencils, reservations)"

ACROSS = [  # label, substring (inclusive, the largest match)
    ("SurfaceCoverage::place", "topotet::SurfaceCoverage::place("),
    ("placement_within_tolerance", "topotet::placement_within_tolerance("),
    ("check_link_conditions", "topotet::check_link_conditions("),
    ("first_acceptable", "topotet::first_acceptable("),
    ("CostModel::edge_cost", "topotet::CostModel::edge_cost("),
    ("CostModel::candidates", "topotet::CostModel::candidates("),
    ("collapse", "topotet::collapse("),
    ("InputSamples::inside", "topotet::InputSamples::inside("),
    ("MeshModel::neighbours", "MeshModel::neighbours("),
]


# --- callgrind_annotate ----------------------------------------------------------------------------

LINE = re.compile(r"^\s*([\d,]+)\s+\(\s*[\d.]+%\)\s+([<>*])\s+(.*)$")
TAIL = re.compile(r"^(?P<fn>.*?)(?: \((?P<calls>[\d,]+)x\))?(?: \[(?P<obj>/[^\[\]]*|\?\?\?)\])?$")


def num(s):
    return int(s.replace(",", ""))


class Profile:
    """Inclusive counts of every function, and the call arcs (inclusive cost along each arc)."""

    def __init__(self, text):
        self.total = None
        self.target = None
        self.incl = {}      # key -> inclusive instructions
        self.func = {}      # key -> function name (without the file)
        self.callers = {}   # key -> [(caller key, cost)]
        self.callees = {}   # key -> [(callee key, cost)]
        block = []
        for line in text.splitlines():
            m = re.match(r"^\s*([\d,]+)\s+\(\s*[\d.]+%\)\s+PROGRAM TOTALS", line)
            if m:
                self.total = num(m.group(1))
                continue
            if line.startswith("Profiled target:"):
                self.target = re.sub(r"\s*\(PID \d+.*\)\s*$", "", line.split(":", 1)[1].strip())
                continue
            m = LINE.match(line)
            if m:
                block.append((num(m.group(1)), m.group(2), self._key(m.group(3))))
            elif not line.strip():
                self._block(block)
                block = []
        self._block(block)
        if self.total is None:
            raise SystemExit("no PROGRAM TOTALS line in the callgrind_annotate output")

    def _key(self, rest):
        m = TAIL.match(rest.strip())
        fn, obj = m.group("fn"), m.group("obj") or ""
        key = f"{fn} [{obj}]"
        # "file:function": the file is ??? without debug information, else a path (no colon).
        self.func.setdefault(key, fn.split(":", 1)[1] if re.match(r"^[^:(<\s]*:", fn) else fn)
        return key

    def _block(self, block):
        stars = [k for c, kind, k in block if kind == "*"]
        if not stars:
            return
        me = stars[0]
        for c, kind, k in block:
            if kind == "*":
                self.incl[me] = max(self.incl.get(me, 0), c)
            elif kind == "<":
                self.callers.setdefault(me, []).append((k, c))
            else:
                self.callees.setdefault(me, []).append((k, c))

    def matches(self, substrings):
        return [k for k in self.incl if any(s in self.func[k] for s in substrings)]

    def top(self, substrings):
        """The largest inclusive count among the matches (they nest: a function, its lambdas, the
        TBB wrappers of its loops)."""
        ks = self.matches(substrings)
        return max(ks, key=lambda k: self.incl[k]) if ks else None

    def self_cost(self, key):
        return self.incl[key] - sum(c for _, c in self.callees.get(key, []))

    def inside(self, key, substrings, depth=6):
        """Instructions of `key` spent in calls from functions matching `substrings`: through its
        direct callers, and up chains of wrappers with a single caller (std::function handlers)."""
        total = 0
        frontier = [(key, self.incl[key])]
        seen = {key}
        for _ in range(depth):
            nxt = []
            for k, budget in frontier:
                for caller, c in self.callers.get(k, []):
                    c = min(c, budget)
                    if any(s in self.func[caller] for s in substrings):
                        total += c
                    elif caller not in seen and len(self.callers.get(caller, [])) == 1:
                        seen.add(caller)
                        nxt.append((caller, c))
            frontier = nxt
        return total


def breakdown(prof):
    fams = []
    notes = []
    roots = {}  # family -> [root keys]
    for name, groups, _ in FAMILIES:
        roots[name] = [k for k in (prof.top(g) for g in groups) if k is not None]
    patterns = {name: [s for g in groups for s in g] for name, groups, _ in FAMILIES}
    loop = next((k for k in (prof.top([s]) for s in ROUND_LOOP) if k is not None), None)
    for name, groups, arcs in FAMILIES:
        value = sum(prof.incl[k] for k in roots[name])
        parts = {prof.func[k]: prof.incl[k] for k in roots[name]}
        # Calls made straight from the round loop (batches smaller than a grain run inline).
        if arcs and loop is not None:
            for callee, c in prof.callees.get(loop, []):
                if any(s in prof.func[callee] for s in arcs):
                    value += c
                    parts[f"round loop -> {prof.func[callee]}"] = c
        # Other families' top-level functions called from inside this one.
        for other, _, _ in FAMILIES:
            if other == name:
                continue
            for r in roots[other]:
                if any(s in prof.func[r] for s in patterns[name]):
                    continue
                c = prof.inside(r, patterns[name])
                if c:
                    value -= c
                    parts[f"minus {other}"] = parts.get(f"minus {other}", 0) - c
        fams.append({"name": name, "instructions": value, "parts": parts})
    # Rounds::threshold (and the round loop's own bookkeeping) is inlined into the round loop:
    # its instructions are the loop's own.
    if loop is not None and not prof.matches(["Rounds::threshold("]):
        own = prof.self_cost(loop)
        for f in fams:
            if f["name"] == SELECT:
                f["instructions"] += own
                f["parts"]["round loop's own instructions (threshold, inlined)"] = own
        notes.append(f"select includes the round loop's own instructions ({prof.func[loop].split('(')[0]}, "
                     f"{own / 1e6:.1f} M): Rounds::threshold is inlined there (with the loops of evaluate and "
                     "verify over batches smaller than a grain)")
    init = next((f for f in fams if f["name"] == "initial proposals"), None)
    if init is not None and roots["initial proposals"] and init["instructions"] < 0.005 * prof.total:
        notes.append("initial proposals: the Rounds constructor makes none in this build (it builds the cost "
                     "model and the dirty list); round 1's evaluate proposes every vertex, counted in evaluate")
    # Families the run never entered (the sequential engine in a parallel run, no stall) are left out.
    fams = [f for f in fams if roots[f["name"]] or f["instructions"]]
    other = prof.total - sum(f["instructions"] for f in fams)
    fams.append({"name": "other", "instructions": other, "parts": {}})
    if other < -0.01 * prof.total:
        notes.append("the families add up to more than the total: two of them overlap (check the patterns)")
    elif other > 0.05 * prof.total:
        notes.append("more than 5% of the instructions fall in no family (check the patterns against the profile)")
    across = []
    for label, s in ACROSS:
        k = prof.top([s])
        if k is not None:
            across.append({"name": label, "instructions": prof.incl[k]})
    return fams, across, notes


# --- topotet's report -------------------------------------------------------------------------------

def parse_report(text):
    r = {}
    for line in text.splitlines():
        if line.startswith("work") and "collapses" in line:
            m = re.search(r"([\d,]+) collapses?", line)
            if m:
                r["collapses"] = num(m.group(1))
            m = re.search(r"([\d.,]+) evaluations/collapse", line)
            if m:
                r["evaluations_per_collapse"] = float(m.group(1).replace(",", ""))
            m = re.search(r"([\d,]+) legality checks", line)
            if m:
                r["legality_checks"] = num(m.group(1))
        elif line.startswith("rejected"):
            m = re.search(r"inversion ([\d,]+)", line)
            if m:
                r["inversion_refusals"] = num(m.group(1))
    if "collapses" not in r:
        raise SystemExit("no 'work ... collapses' line in topotet's report")
    return r


# --- output -----------------------------------------------------------------------------------------

def result(prof, report, command):
    fams, across, notes = breakdown(prof)
    n = report["collapses"]
    total = prof.total

    def row(f):
        return {"name": f["name"], "instructions": f["instructions"],
                "k_per_collapse": f["instructions"] / n / 1e3 if n else None,
                "share": f["instructions"] / total if total else None}

    per = lambda key: report[key] / n if n and key in report else None
    return {
        "command": command,
        "total_instructions": total,
        "collapses": n,
        "instructions_per_collapse": total / n if n else None,
        "evaluations_per_collapse": report.get("evaluations_per_collapse"),
        "legality_checks_per_collapse": per("legality_checks"),
        "inversion_refusals_per_collapse": per("inversion_refusals"),
        "families": [dict(row(f), parts=f["parts"]) for f in fams],
        "across_phases": [row(f) for f in across],
        "notes": notes,
    }


def fmt(x, spec):
    return "-" if x is None else format(x, spec)


def print_table(r, out=sys.stdout, verbose=False):
    w = max(len(f["name"]) for f in r["families"] + r["across_phases"]) + 4
    p = lambda s="": print(s, file=out)
    p(f"{'family':<{w}} {'k instr/collapse':>16} {'share':>7} {'M instr':>10}")
    for f in r["families"]:
        p(f"{f['name']:<{w}} {fmt(f['k_per_collapse'], '16.1f')} {fmt(100 * f['share'], '6.1f')}% "
          f"{f['instructions'] / 1e6:10.1f}")
        if verbose:
            for k, v in f["parts"].items():
                p(f"      {v / 1e6:10.1f} M  {k[:150]}")
    tk = r["instructions_per_collapse"] / 1e3 if r["instructions_per_collapse"] else None
    p(f"{'total':<{w}} {fmt(tk, '16.1f')} {100.0:6.1f}% {r['total_instructions'] / 1e6:10.1f}")
    p()
    p("across phases (inclusive; they overlap the rows above):")
    for f in r["across_phases"]:
        p(f"  {f['name']:<{w - 2}} {fmt(f['k_per_collapse'], '16.1f')} {fmt(100 * f['share'], '6.1f')}% "
          f"{f['instructions'] / 1e6:10.1f}")
    p()
    p(f"instructions {r['total_instructions']:,}, collapses {r['collapses']:,}, "
      f"instructions/collapse {fmt(r['instructions_per_collapse'], ',.0f')}")
    p(f"evaluations/collapse {fmt(r['evaluations_per_collapse'], '.1f')}, "
      f"legality checks/collapse {fmt(r['legality_checks_per_collapse'], '.2f')}, "
      f"inversion refusals/collapse {fmt(r['inversion_refusals_per_collapse'], '.2f')}")
    for note in r["notes"]:
        p(f"note: {note}")
    p(f"command: {r['command']}")


def recorded_command(callgrind_file):
    """The profiled command line, from the callgrind file's header."""
    with open(callgrind_file, errors="replace") as f:
        for _, line in zip(range(50), f):
            if line.startswith("cmd:"):
                return line[4:].strip()
    return None


def annotate(callgrind_file):
    if shutil.which("callgrind_annotate") is None:
        raise SystemExit("callgrind_annotate not found (install valgrind)")
    out = subprocess.run(["callgrind_annotate", "--inclusive=yes", "--tree=both", "--threshold=100", "--auto=no",
                          str(callgrind_file)], capture_output=True, text=True)
    if out.returncode != 0:
        raise SystemExit(f"callgrind_annotate failed:\n{out.stderr}")
    return Profile(out.stdout)


def main():
    argv = sys.argv[1:]
    options = []
    if "--" in argv:
        i = argv.index("--")
        argv, options = argv[:i], argv[i + 1:]
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 usage="%(prog)s [--topotet PATH] [--keep OUT.callgrind] [--json FILE] "
                                       "INPUT -- [simplify options...]\n"
                                       "       %(prog)s --from-callgrind FILE --report REPORT.txt [--json FILE]")
    ap.add_argument("input", nargs="?", help="input mesh")
    ap.add_argument("--topotet", default=str(ROOT / "build" / "cli" / "topotet"), help="topotet binary")
    ap.add_argument("--keep", metavar="OUT", help="keep the callgrind file as OUT (and the report as OUT.report.txt)")
    ap.add_argument("--json", metavar="FILE", help="also write the result as JSON (- = stdout)")
    ap.add_argument("--from-callgrind", metavar="FILE", help="analyse an existing callgrind file, without running")
    ap.add_argument("--report", metavar="FILE", help="with --from-callgrind: topotet's saved stdout")
    ap.add_argument("--parts", action="store_true", help="also print the functions each family is made of")
    a = ap.parse_args(argv)

    if a.from_callgrind:
        if a.input or options:
            ap.error("--from-callgrind takes no INPUT nor simplify options")
        if not a.report:
            ap.error("--from-callgrind needs --report REPORT.txt (topotet's stdout of that run)")
        prof = annotate(a.from_callgrind)
        report = parse_report(Path(a.report).read_text())
        command = f"(from {a.from_callgrind}) {recorded_command(a.from_callgrind) or prof.target or '?'}"
    else:
        if not a.input:
            ap.error("INPUT is required (or --from-callgrind FILE --report REPORT.txt)")
        if any(o in ("-o", "--output") or o.startswith("--output=") for o in options):
            ap.error("the output mesh goes to a temporary folder: leave -o/--output out of the options")
        if shutil.which("valgrind") is None:
            raise SystemExit("valgrind not found")
        if not os.access(a.topotet, os.X_OK):
            raise SystemExit(f"no topotet binary at {a.topotet} (--topotet PATH)")
        extra = []
        if not any(o == "--threads" or o.startswith("--threads=") for o in options):
            extra += ["--threads", "1"]
        if "--no-metrics" not in options:
            extra.append("--no-metrics")
        with tempfile.TemporaryDirectory(prefix="instruction_breakdown.") as tmp:
            cg = Path(tmp) / "callgrind.out"
            cmd = ["valgrind", "--tool=callgrind", f"--callgrind-out-file={cg}", a.topotet, "simplify", a.input,
                   "-o", str(Path(tmp) / "out.mesh")] + extra + options
            print(f"running: {shlex.join(cmd)}", file=sys.stderr, flush=True)
            run = subprocess.run(cmd, capture_output=True, text=True)
            if run.returncode != 0:
                print(f"warning: topotet exited with {run.returncode}; its stderr ends with:\n"
                      + "\n".join(run.stderr.splitlines()[-15:]), file=sys.stderr)
            if not cg.exists() or "collapses" not in run.stdout:
                print(run.stdout, file=sys.stderr)
                raise SystemExit("the run produced no callgrind file or no report")
            if a.keep:
                shutil.copyfile(cg, a.keep)
                Path(a.keep + ".report.txt").write_text(run.stdout)
            prof = annotate(cg)
        report = parse_report(run.stdout)
        command = shlex.join(cmd)
    r = result(prof, report, command)
    print_table(r, out=sys.stderr if a.json == "-" else sys.stdout, verbose=a.parts)
    if a.json:
        text = json.dumps(r, indent=2) + "\n"
        if a.json == "-":
            sys.stdout.write(text)
        else:
            Path(a.json).write_text(text)


if __name__ == "__main__":
    main()
