#!/usr/bin/env python3
"""Error-bounded levels (issue #49, item 4): for one input with fields, one row per relative field
error bound eps (of each field component's range): vertices reached, time, the largest field error
measured densely against the original (--points points inside the original's tets, uniform in
each, plus every original vertex), beside the bound.

  python3 bench/levels_error_table.py INPUT [--topotet build/cli/topotet] [--eps 0.005,0.01,0.02,0.05]
      [--threads 1] [--ratio 0.02] [--points 1000000] [--everywhere-eps 0.01,0.05]
      [--everywhere-timeout 200] [--everywhere-hierarchy] [--work DIR] [--json FILE]

Three tables:
  (a) levels: one `simplify --hierarchy H --levels-error eps,...` run (vertex mode, base at --ratio);
      each level file measured here, against the original.
  (b) separate runs `simplify --max-field-error-rel eps --ratio R` in vertex mode, and (c) with
      `--field-bound-mode everywhere` for --everywhere-eps (each run killed after
      --everywhere-timeout s): the CLI's own dense check (JSON field_bounds.dense, 100,000 points)
      and this script's measurement at --points.
  --everywhere-hierarchy: also `simplify --field-bound-mode everywhere --max-field-error-rel
      max(eps) --hierarchy` with --levels-error at the smaller eps, its levels measured here (does
      extraction keep the everywhere bound?).

The dense measurement is this script's own (numpy + scipy, the topotet Python module only to read
meshes): the CLI measures 100,000 points and only in `simplify`; neither `extract`, `check` nor the
Python module measures a given file against the original densely. A point is located in the
simplified mesh by the tets of the nearest centroids (then more of them); points no simplified tet
holds (its boundary moved inward) are counted as `outside` and not compared, as the library does.
Errors are |f_orig - f_simp| / range of the component over the original's vertices, the worst
component. Needs the Python module (build/python) and numpy, scipy.
"""
import argparse, json, os, subprocess, sys, time

HERE = os.path.dirname(os.path.abspath(__file__))


def load_module(topotet_bin):
    for cand in [os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(topotet_bin))), "python"),
                 os.path.join(HERE, "..", "build", "python")]:
        if os.path.isdir(os.path.join(cand, "topotet")):
            sys.path.insert(0, cand)
            break
    import topotet  # noqa: E402
    return topotet


def components(mesh):
    import numpy as np
    out = []
    for name, a in mesh["fields"].items():
        a = np.asarray(a, dtype=np.float64)
        if a.ndim == 1:
            out.append((name, 0, a))
        else:
            out.extend((name, c, a[:, c]) for c in range(a.shape[1]))
    return out


def dense_error(orig, simp, points, seed=1, chunk=100000):
    """Largest field error of simp against orig at `points` points uniform in orig's tets (point i in
    tet i mod T) and at every original vertex used by a tet."""
    import numpy as np
    from scipy.spatial import cKDTree
    P0 = np.asarray(orig["points"], np.float64)
    T0 = np.asarray(orig["tets"], np.int64)
    P1 = np.asarray(simp["points"], np.float64)
    T1 = np.asarray(simp["tets"], np.int64)
    rng = np.random.default_rng(seed)
    used = np.unique(T0)
    c0 = {(n, c): a for n, c, a in components(orig)}
    comps = [(n, c, c0[(n, c)], a) for n, c, a in components(simp) if (n, c) in c0]
    ranges = []
    for _, _, a0, _ in comps:
        r = a0[used].max() - a0[used].min()
        ranges.append(r if r > 0 else 1.0)
    # Per simplified tet: v0 and the inverse of [v1-v0, v2-v0, v3-v0].
    V = P1[T1]
    M = np.stack([V[:, 1] - V[:, 0], V[:, 2] - V[:, 0], V[:, 3] - V[:, 0]], axis=2)  # columns
    Minv = np.linalg.inv(M)
    tree = cKDTree(V.mean(axis=1))
    lo, hi = V.min(axis=1), V.max(axis=1)
    # The samples: (original tet, barycentric weights).
    tet_of = np.concatenate([np.arange(points, dtype=np.int64) % len(T0), np.zeros(len(used), np.int64)])
    corner_t = np.full(len(P0), -1, np.int64)
    for k in range(4):  # a tet holding each vertex (its corner index is found per chunk)
        corner_t[T0[:, k]] = np.arange(len(T0))
    tet_of[points:] = corner_t[used]
    total = len(tet_of)
    res = {"points": 0, "outside": 0, "max_error_rel": 0.0, "per_component": {}, "fallback": 0}
    worst = np.zeros(len(comps))
    above = {}
    errs_all = []
    for s in range(0, total, chunk):
        e = min(total, s + chunk)
        t = tet_of[s:e]
        n = e - s
        W = np.zeros((n, 4))
        ni = max(0, min(points, e) - s)
        if ni:
            W[:ni] = -np.log(1.0 - rng.random((ni, 4)))
            W[:ni] /= W[:ni].sum(axis=1, keepdims=True)
        if ni < n:
            vv = used[s + ni - points:e - points]
            kk = np.argmax(T0[t[ni:]] == vv[:, None], axis=1)
            W[np.arange(ni, n), kk] = 1.0
        Q = np.einsum("nk,nkd->nd", W, P0[T0[t]])
        found = np.full(n, -1, np.int64)
        B = np.zeros((n, 4))
        todo = np.arange(n)
        for k in (8, 64, 512):
            if len(todo) == 0:
                break
            k = min(k, len(T1))
            _, cand = tree.query(Q[todo], k=k)
            cand = cand.reshape(len(todo), k)
            d = Q[todo][:, None, :] - V[cand, 0]
            b = np.einsum("nkij,nkj->nki", Minv[cand], d)
            b0 = 1.0 - b.sum(axis=2)
            mn = np.minimum(b0, b.min(axis=2))
            ok = mn >= -1e-9
            hit = ok.any(axis=1)
            j = np.argmax(ok, axis=1)
            rows = todo[hit]
            found[rows] = cand[hit, j[hit]]
            B[rows, 0] = b0[hit, j[hit]]
            B[rows, 1:] = b[hit, j[hit]]
            todo = todo[~hit]
        # Brute force by bounding boxes for what is left (a few): the tet of largest min-bary.
        for r in todo[:5000]:
            q = Q[r]
            m = np.nonzero(((lo <= q + 1e-12) & (hi >= q - 1e-12)).all(axis=1))[0]
            if len(m):
                b = np.einsum("kij,kj->ki", Minv[m], q - V[m, 0])
                b0 = 1.0 - b.sum(axis=1)
                mn = np.minimum(b0, b.min(axis=1))
                i = int(np.argmax(mn))
                if mn[i] >= -1e-9:
                    found[r] = m[i]
                    B[r, 0], B[r, 1:] = b0[i], b[i]
                    res["fallback"] += 1
        inside = found >= 0
        res["outside"] += int((~inside).sum())
        res["points"] += int(inside.sum())
        ti, fi = t[inside], found[inside]
        Wi, Bi = W[inside], B[inside]
        for ci, (name, c, a0, a1) in enumerate(comps):
            f = np.einsum("nk,nk->n", Wi, a0[T0[ti]])
            g = np.einsum("nk,nk->n", Bi, a1[T1[fi]])
            err = np.abs(f - g) / ranges[ci]
            if len(err):
                worst[ci] = max(worst[ci], float(err.max()))
                errs_all.append(err.astype(np.float32))
    for ci, (name, c, _, _) in enumerate(comps):
        res["per_component"][f"{name}[{c}]" if len(comps) > 1 else name] = float(worst[ci])
    res["max_error_rel"] = float(worst.max()) if len(worst) else 0.0
    res["_errors"] = np.concatenate(errs_all) if errs_all else np.zeros(0, np.float32)
    return res


def run(cmd, log, timeout=None):
    t0 = time.time()
    try:
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
        rc, out, err = p.returncode, p.stdout, p.stderr
    except subprocess.TimeoutExpired as e:
        rc, out, err = "timeout", (e.stdout or b"").decode() if isinstance(e.stdout, bytes) else (e.stdout or ""), ""
    wall = time.time() - t0
    with open(log, "w") as f:
        f.write("$ " + " ".join(cmd) + f"\n# rc={rc} wall={wall:.2f}s\n" + out + "\n--- stderr\n" + err)
    return rc, out, wall


def levels_of(report_path):
    """The --levels-error rows of a simplify JSON report (error_levels); none if it is missing."""
    try:
        rows = json.load(open(report_path)).get("error_levels", [])
    except (OSError, ValueError):
        return []
    return [{"eps": r["error"], "vertices": r["vertices"], "tets": r["tets"], "max_both": r["field_max_rel"],
             "max_at_orig": f"{r['field_max_rel_at_original']:.3g}",
             "bound": "-" if r["bound"] is None else f"{r['bound']:.3g}", "extract_seconds": r["extract_seconds"],
             "topology": r["topology"].upper()} for r in rows]


def print_levels(rows, points, with_tets_and_topology):
    """One table row per level: its size, the CLI's numbers, and this script's dense measurement."""
    extra = with_tets_and_topology
    print(f"| eps | #vert |{' #tets |' if extra else ''} max@orig (CLI) | bound (CLI) | max at {points} pts + vertices | "
          f"above eps | outside |{' topology |' if extra else ''}")
    print("|---" * (9 if extra else 7) + "|")
    for r in rows:
        d = r["dense"]
        tets = f" {r['tets']:,} |" if extra else ""
        topology = f" {r['topology']} |" if extra else ""
        print(f"| {r['eps']:g} | {r['vertices']:,} |{tets} {r['max_at_orig']} | {r['bound']} | {d['max_error_rel']:.4g} | "
              f"{d['above_bound']:,} | {d['outside']:,} |{topology}")


def level_path(out, eps):
    base, ext = os.path.splitext(out)
    return f"{base}_{eps:g}{ext}"


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("input")
    ap.add_argument("--topotet", default=os.path.join(HERE, "..", "build", "cli", "topotet"))
    ap.add_argument("--eps", default="0.005,0.01,0.02,0.05")
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--ratio", type=float, default=0.02, help="target of every run (the bound should stop it first)")
    ap.add_argument("--points", type=int, default=1000000)
    ap.add_argument("--everywhere-eps", default="", help="eps to run with --field-bound-mode everywhere (default none)")
    ap.add_argument("--everywhere-timeout", type=float, default=200)
    ap.add_argument("--everywhere-hierarchy", action="store_true")
    ap.add_argument("--name", default=None)
    ap.add_argument("--work", default="/tmp/levels_error_table")
    ap.add_argument("--json", default=None)
    a = ap.parse_args()
    import numpy as np
    topotet = load_module(a.topotet)
    eps = [float(x) for x in a.eps.split(",") if x]
    eeps = [float(x) for x in a.everywhere_eps.split(",") if x]
    name = a.name or os.path.basename(a.input).split(".")[0]
    os.makedirs(a.work, exist_ok=True)
    W = lambda f: os.path.join(a.work, f"{name}_{f}")
    T = [a.topotet, "simplify", a.input, "--threads", str(a.threads), "--progress", "none", "--ratio", str(a.ratio)]
    orig = topotet.read(a.input)
    result = {"input": a.input, "tets": int(len(orig["tets"])), "vertices": int(len(orig["points"])),
              "points": a.points, "threads": a.threads, "ratio": a.ratio, "levels": [], "runs": [], "everywhere_levels": []}

    def measure(path, bound):
        t0 = time.time()
        d = dense_error(orig, topotet.read(path), a.points)
        errs = d.pop("_errors")
        d["above_bound"] = int((errs > bound * (1 + 1e-6)).sum())
        d["measure_seconds"] = round(time.time() - t0, 2)
        return d

    # (a) levels from one hierarchy run.
    out = W("h.mesh")
    cmd = T + ["-o", out, "--hierarchy", W("h.tth"), "--levels-error", ",".join(f"{e:g}" for e in eps), "--json", W("h.json")]
    rc, _, wall = run(cmd, W("h.log"))
    result["hierarchy_run"] = {"command": " ".join(cmd), "rc": rc, "wall_seconds": round(wall, 2)}
    try:
        result["hierarchy_run"]["simplify_seconds"] = json.load(open(W("h.json")))["levels"][-1]["simplify_seconds"]
    except Exception:
        pass
    for row in levels_of(W("h.json")):
        row.update(dense=measure(level_path(out, row["eps"]), row["eps"]))
        result["levels"].append(row)

    # (b), (c) separate bounded runs.
    for mode, elist in (("vertices", eps), ("everywhere", eeps)):
        for e in elist:
            o = W(f"{mode}_{e:g}.mesh")
            cmd = T + ["-o", o, "--max-field-error-rel", f"{e:g}", "--field-bound-mode", mode, "--json", W(f"{mode}_{e:g}.json")]
            rc, text, wall = run(cmd, W(f"{mode}_{e:g}.log"), a.everywhere_timeout if mode == "everywhere" else None)
            r = {"mode": mode, "eps": e, "command": " ".join(cmd), "rc": rc, "wall_seconds": round(wall, 2)}
            if rc != "timeout" and os.path.exists(W(f"{mode}_{e:g}.json")):
                l = json.load(open(W(f"{mode}_{e:g}.json")))["levels"][-1]
                fb = l.get("field_bounds") or {}
                r.update(vertices=l["vertices_after"], tets=l["tets_after"], simplify_seconds=l["simplify_seconds"],
                         rejected_field_error=l["rejected"]["field_error"], bound=fb.get("max_bound_rel", fb.get("bound_rel")),
                         cli_dense=fb.get("dense"), cli_field_bounds=fb)
                r["dense"] = measure(o, e)
            result["runs"].append(r)

    # Levels of an everywhere hierarchy.
    if a.everywhere_hierarchy and eps:
        top = max(eps)
        o = W("eh.mesh")
        cmd = T + ["-o", o, "--hierarchy", W("eh.tth"), "--field-bound-mode", "everywhere", "--max-field-error-rel", f"{top:g}",
                   "--levels-error", ",".join(f"{e:g}" for e in eps), "--json", W("eh.json")]
        rc, _, wall = run(cmd, W("eh.log"), a.everywhere_timeout)
        result["everywhere_hierarchy_run"] = {"command": " ".join(cmd), "rc": rc, "wall_seconds": round(wall, 2)}
        if rc != "timeout":
            for row in levels_of(W("eh.json")):
                row.update(dense=measure(level_path(o, row["eps"]), row["eps"]))
                result["everywhere_levels"].append(row)

    # Tables.
    P = f"{a.points:,}"
    print(f"\n### {name}: {result['tets']:,} tets, {result['vertices']:,} vertices; threads {a.threads}\n")
    h = result["hierarchy_run"]
    print(f"(a) levels from one run (`{h['command']}`: wall {h['wall_seconds']} s, simplify "
          f"{h.get('simplify_seconds', float('nan')):.1f} s; each level extracted in ms)\n")
    print_levels(result["levels"], P, True)
    print(f"\n(b/c) separate runs `--max-field-error-rel eps --ratio {a.ratio}`\n")
    print(f"| mode | eps | #vert | wall s | simplify s | CLI dense max (100k) | CLI above bound | max at {P} pts + vertices | above eps | outside |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for r in result["runs"]:
        if "dense" not in r:
            print(f"| {r['mode']} | {r['eps']:g} | - | {r['wall_seconds']} ({r['rc']}) | - | - | - | - | - | - |")
            continue
        cd, d = r.get("cli_dense") or {}, r["dense"]
        print(f"| {r['mode']} | {r['eps']:g} | {r['vertices']:,} | {r['wall_seconds']} | {r['simplify_seconds']:.1f} | "
              f"{cd.get('max_error_rel', float('nan')):.4g} | {cd.get('above_bound', '-')} | {d['max_error_rel']:.4g} | "
              f"{d['above_bound']:,} | {d['outside']:,} |")
    if result["everywhere_levels"] or "everywhere_hierarchy_run" in result:
        h = result["everywhere_hierarchy_run"]
        print(f"\n(d) levels of an everywhere hierarchy (`{h['command']}`: wall {h['wall_seconds']} s, rc {h['rc']})\n")
        print_levels(result["everywhere_levels"], P, False)
    js = a.json or W("table.json")
    with open(js, "w") as f:
        json.dump(result, f, indent=1, default=str)
    print(f"\nJSON: {js}")


if __name__ == "__main__":
    main()
