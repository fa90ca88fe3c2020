#!/usr/bin/env python3
"""Even sizes (issue #26, item 5): the size term (`--size-weight W`) against the error alone, side by side.

For every input and ratio: `topotet simplify IN -o OUT.mesh --ratio R --threads T --size-weight W --json J`
with the defaults otherwise (`--optimize light` included), then the output's grading, read from OUT:
  - pairs > 2: the share of pairs of edges meeting at a vertex of one triangle (each triangle of the mesh
    counted once, 3 pairs) whose lengths differ by more than 2x;
  - grading > 1.5: the share of edges uv whose ends' mean incident edge lengths differ by more than 1.5x
    (how fast the size changes from a vertex to the next);
  - surface / interior: the mean length of boundary edges over that of interior edges (1 = one size);
  - boundary triangles (on the families and the ball in a cube, all on flat faces of the box);
and, from the report: min dihedral, tets under 10 degrees, field RMS (relative to the range), vertices
reached (of the input), simplify seconds, topology verdict.

    python3 bench/size_grading.py build/cli/topotet --work /tmp/sg --weights 0,1e-4
    python3 bench/size_grading.py build/cli/topotet --only 'ball|slab' --ratios 0.1
Pure Python (no numpy): fine up to a few 100k output tets.
"""
import argparse
import gzip
import json
import math
import os
import re
import shutil
import subprocess
import sys

from inputs import FAMILIES, family, shared


def gmsh_mesh(work, name, geo):
    """The OpenCASCADE model `geo` meshed by gmsh into WORK/NAME.msh once (written to a temporary name
    and renamed); None without gmsh."""
    path = os.path.join(work, f"{name}.msh")
    if not os.path.exists(path):
        if shutil.which("gmsh") is None:
            return None
        geo_path = os.path.join(work, f"{name}.geo")
        with open(geo_path, "w") as f:
            f.write(geo)
        subprocess.run(["gmsh", "-3", geo_path, "-o", path + ".part.msh", "-format", "msh41", "-nt", "1"], check=True,
                       stdout=subprocess.DEVNULL)
        os.replace(path + ".part.msh", path)
    return path


def ball_in_cube(work, size=0.03):
    """bench/gmsh_smooth.sh's ball in a cube (2 materials)."""
    return gmsh_mesh(work, f"ball_{size}",
                     'SetFactory("OpenCASCADE");\nBox(1) = {0, 0, 0, 1, 1, 1};\nSphere(2) = {0.5, 0.5, 0.5, 0.3};\n'
                     "BooleanFragments{ Volume{1}; Delete; }{ Volume{2}; Delete; }\n"
                     'Physical Volume("ball", 1) = {2};\nPhysical Volume("box", 2) = {3};\n'
                     f"Mesh.MeshSizeMax = {size};\nMesh.MeshSizeMin = {size};\n")


def cube_in_sphere(work, size=0.058):
    """Issue #26's case: a cube inside a ball (2 materials, the cube's faces a flat interface); ~100k tets."""
    return gmsh_mesh(work, f"cube_in_sphere_{size}",
                     'SetFactory("OpenCASCADE");\nSphere(1) = {0, 0, 0, 1};\nBox(2) = {-0.4, -0.4, -0.4, 0.8, 0.8, 0.8};\n'
                     "BooleanFragments{ Volume{1}; Delete; }{ Volume{2}; Delete; }\n"
                     'Physical Volume("shell", 1) = {3};\nPhysical Volume("cube", 2) = {2};\n'
                     f"Mesh.MeshSizeMax = {size};\nMesh.MeshSizeMin = {size};\n")


def inputs(topotet, work, tets):
    out = [(f"{name} {tets // 1000}k", family(topotet, work, name, tets)) for name in FAMILIES]
    ball = ball_in_cube(work)
    if ball:
        out.append(("gmsh ball-in-cube", ball))
    cube = cube_in_sphere(work)
    if cube:
        out.append(("gmsh cube-in-sphere", cube))
    for rel in ("mmg/tinyBoxt.mesh", "simnibs/sphere3.msh", "palace/circular_hole.msh", "volume/lox_post_tets.mesh.gz"):
        path = shared(rel)
        if path:
            out.append((os.path.basename(rel).split(".")[0], path))
    return out


def read_medit(path):
    """Vertices and tets (0-based) of a MEDIT .mesh (ASCII, optionally .gz)."""
    opener = gzip.open if path.endswith(".gz") else open
    with opener(path, "rt") as f:
        tokens = f.read().split()
    xyz, tets, refs, i = [], [], [], 0
    while i < len(tokens):
        t = tokens[i]
        if t == "Vertices":
            n = int(tokens[i + 1])
            i += 2
            xyz = [(float(tokens[i + 4 * k]), float(tokens[i + 4 * k + 1]), float(tokens[i + 4 * k + 2])) for k in range(n)]
            i += 4 * n
        elif t == "Tetrahedra":
            n = int(tokens[i + 1])
            i += 2
            tets = [tuple(int(tokens[i + 5 * k + j]) - 1 for j in range(4)) for k in range(n)]
            refs = [int(tokens[i + 5 * k + 4]) for k in range(n)]
            i += 5 * n
        else:
            i += 1
    return xyz, tets, refs


def grading(path):
    xyz, tets, refs = read_medit(path)
    faces, face_refs = {}, {}
    for t, ref in zip(tets, refs):
        for skip in range(4):
            f = tuple(sorted(t[j] for j in range(4) if j != skip))
            faces[f] = faces.get(f, 0) + 1
            face_refs.setdefault(f, set()).add(ref)
    interface_faces = sum(1 for f, c in faces.items() if c == 2 and len(face_refs[f]) == 2)
    length = {}

    def edge(a, b):
        key = (a, b) if a < b else (b, a)
        if key not in length:
            p, q = xyz[a], xyz[b]
            length[key] = math.dist(p, q)
        return length[key]

    pairs = pairs_over = 0
    boundary_edges = set()
    boundary_faces = 0
    for (a, b, c), count in faces.items():
        lab, lbc, lca = edge(a, b), edge(b, c), edge(c, a)
        for x, y in ((lab, lbc), (lbc, lca), (lca, lab)):
            pairs += 1
            if max(x, y) > 2.0 * min(x, y):
                pairs_over += 1
        if count == 1:
            boundary_faces += 1
            for e in ((a, b), (b, c), (c, a)):
                boundary_edges.add((min(e), max(e)))
    for t in tets:  # edges inside no face? every edge is in a face; make sure all are measured
        for i in range(4):
            for j in range(i + 1, 4):
                edge(t[i], t[j])
    total = [0.0] * len(xyz)
    count = [0] * len(xyz)
    for (a, b), l in length.items():
        total[a] += l
        total[b] += l
        count[a] += 1
        count[b] += 1
    h = [total[v] / count[v] if count[v] else 0.0 for v in range(len(xyz))]
    graded_over = sum(1 for (a, b) in length if max(h[a], h[b]) > 1.5 * min(h[a], h[b]))
    surface = [length[e] for e in boundary_edges]
    interior = [l for e, l in length.items() if e not in boundary_edges]
    ratio = (sum(surface) / len(surface)) / (sum(interior) / len(interior)) if surface and interior else float("nan")
    return {
        "pairs_over_2": pairs_over / pairs if pairs else 0.0,
        "grading_over_1_5": graded_over / len(length) if length else 0.0,
        "surface_over_interior": ratio,
        "boundary_triangles": boundary_faces,
        "interface_triangles": interface_faces,
    }


def run(topotet, path, ratio, threads, weight, work):
    report = os.path.join(work, "report.json")
    out = os.path.join(work, "out.mesh")
    cmd = [topotet, "simplify", path, "-o", out, "--ratio", str(ratio), "--threads", str(threads),
           "--size-weight", str(weight), "--json", report]
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    with open(report) as f:
        level = json.load(f)["levels"][0]
    q = level["quality"]
    fe = level["field_error"]
    r = {
        "min_dihedral": q["dihedral_deg"]["min"],
        "under10": q["tets_under_10_deg"],
        "tets": q["tets"],
        "mean_ratio": q["mean_ratio"]["mean"],
        "rms": fe["rms_rel"] if fe else None,
        "seconds": level["simplify_seconds"],
        "topology": level.get("topology", "?"),
        "vertices": level["vertices_after"],
        "vertices_in": level["vertices_before"],
    }
    r.update(grading(out))
    return r


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("topotet")
    ap.add_argument("--work", default="/tmp/size_grading")
    ap.add_argument("--tets", type=int, default=100000, help="size of the generated families")
    ap.add_argument("--ratios", default="0.1,0.02")
    ap.add_argument("--weights", default="0,1e-4", help="--size-weight values, comma separated")
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--only", default="", help="regex on the input names")
    ap.add_argument("--json", default="", help="append every run as a JSON line")
    args = ap.parse_args()
    os.makedirs(args.work, exist_ok=True)
    print("| input | asked | size weight | reached | pairs > 2 | grading > 1.5 | surface / interior | boundary / interface tris "
          "| min dihedral | under 10 deg | field RMS | s | topology |")
    print("| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | --- |")
    for name, path in inputs(args.topotet, args.work, args.tets):
        if args.only and not re.search(args.only, name):
            continue
        for ratio in (float(x) for x in args.ratios.split(",")):
            for weight in args.weights.split(","):
                r = run(args.topotet, path, ratio, args.threads, weight, args.work)
                rms = f"{r['rms']:.4f}" if r["rms"] is not None else "-"
                print(f"| {name} | {ratio:g} | {weight} | {100.0 * r['vertices'] / r['vertices_in']:.1f}% "
                      f"| {100.0 * r['pairs_over_2']:.1f}% | {100.0 * r['grading_over_1_5']:.1f}% "
                      f"| {r['surface_over_interior']:.2f} | {r['boundary_triangles']:,} / {r['interface_triangles']:,} | {r['min_dihedral']:.2f} "
                      f"| {r['under10']} ({100.0 * r['under10'] / r['tets']:.1f}%) | {rms} | {r['seconds']:.2f} "
                      f"| {r['topology']} |", flush=True)
                if args.json:
                    with open(args.json, "a") as f:
                        f.write(json.dumps({"input": name, "ratio": ratio, "size_weight": float(weight), **r}) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
