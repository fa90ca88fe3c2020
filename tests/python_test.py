"""The Python module: numpy arrays in and out, the vertex map, read/write round trip, cell arrays, errors.
Run by ctest with PYTHONPATH set to the built module (tests/CMakeLists.txt)."""
import os
import sys
import tempfile

import numpy as np
import topotet


def grid(n, jitter=0.1, seed=1):
    """A jittered Freudenthal grid of n^3 cubes (boundary points stay on the box faces)."""
    g = np.stack(np.meshgrid(*[np.arange(n + 1)] * 3, indexing="ij"), axis=-1).reshape(-1, 3).astype(float)
    rng = np.random.default_rng(seed)
    inner = (g > 0) & (g < n)
    g += np.where(inner, rng.uniform(-jitter, jitter, g.shape), 0.0)
    vid = lambda c: c[..., 0] * (n + 1) ** 2 + c[..., 1] * (n + 1) + c[..., 2]
    cubes = np.stack(np.meshgrid(*[np.arange(n)] * 3, indexing="ij"), axis=-1).reshape(-1, 1, 3)
    tets = []
    for order in [(0, 1, 2), (1, 2, 0), (2, 0, 1), (0, 2, 1), (1, 0, 2), (2, 1, 0)]:
        steps = np.cumsum(np.eye(3, dtype=int)[list(order)], axis=0)
        t = vid(np.concatenate([cubes, cubes + steps], axis=1))
        tets.append(t if np.linalg.det(steps) > 0 else t[:, [0, 1, 3, 2]])
    return g, np.concatenate(tets)


def check(cond, what):
    if not cond:
        print("FAIL:", what)
        sys.exit(1)


points, tets = grid(6)
centres = points[tets].mean(axis=1) - 3.0
materials = np.where((centres**2).sum(axis=1) < 3.0, 2, 1).astype(np.int32)
field = np.stack([points[:, 0], points[:, 1] * points[:, 2], -points[:, 2]], axis=1)  # a 3-vector

# Strided, non-float64 / non-int64 inputs are accepted as they are.
points_f32 = np.asfortranarray(points.astype(np.float32))
tets_i32 = tets.astype(np.int32)
box_corners = [0, len(points) - 1]  # pinned: they never move
out = topotet.simplify(points_f32, tets_i32, materials=materials, fields={"u": field}, ratio=0.3, threads=1,
                       corners=box_corners)
rep = out["report"]
check(rep["status"] in ("ok", "stopped_early"), f"status {rep['status']}")
nv = len(out["points"])
check(nv < len(points) // 2, f"not simplified: {nv} of {len(points)}")
check(rep["vertices_before"] == len(points) and rep["vertices_after"] == nv, "report counts")
check(rep["collapses"] == len(points) - nv, "one collapse per removed vertex")
check(set(rep["rejected"]) == {"link_K", "link_Ktilde", "pinned", "inversion", "quality", "tolerance", "field_error"}, "rejected keys")
check(out["tets"].shape[1] == 4 and out["tets"].min() >= 0 and out["tets"].max() < nv, "output tets")
check(out["fields"]["u"].shape == (nv, 3), "field shape")
check(sorted(np.unique(out["materials"])) == [1, 2], "both materials survive")
check(rep["stopped"] is None if rep["status"] == "ok" else rep["stopped"] is not None, "stopped iff stopped early")

# Equal dtypes that are distinct numpy objects (meshio's .vtu reader makes them) are read as what
# they are: they were once taken for int64 by an identity test ("positions: must hold reals").
twin = lambda a, code: a.astype(np.dtype(code).newbyteorder("="))
check(twin(points, "f8").dtype is not np.dtype(np.float64), "the test makes a distinct float64 dtype")
same = topotet.simplify(twin(points, "f8"), twin(tets, "i8"), materials=twin(materials, "i4"),
                        fields={"u": twin(field, "f8")}, ratio=0.3, threads=1)
usual = topotet.simplify(points, tets, materials=materials, fields={"u": field}, ratio=0.3, threads=1)
check(np.array_equal(same["points"], usual["points"]) and np.array_equal(same["tets"], usual["tets"]),
      "distinct but equal dtypes give the same run")

# The defaults are the library's, guarantees included (they once drifted: tolerance_rel was 0 here).
diag = float(np.linalg.norm(points.max(axis=0) - points.min(axis=0)))
check(abs(rep["tolerance"] - 0.004 * diag) <= 1e-9 * diag, f"default tolerance {rep['tolerance']} for diagonal {diag}")
check(rep["feature_edges"] > 0, "the box's edges are features by default")
off = topotet.simplify(points, tets, materials=materials, ratio=0.3, threads=1, tolerance_rel=0.0, feature_angle=180.0)
check(off["report"]["tolerance"] == 0.0 and off["report"]["feature_edges"] == 0, "guarantees off on request")
plain = topotet.simplify(points, tets, materials=materials, ratio=0.3, threads=1, optimize="none")["report"]
check(plain["optimize_moves"] == 0 and plain["optimize_flips"] == 0 and plain["stall_flips"] == 0,
      "optimize='none' moves and flips nothing, where the collapses stall too")
check(rep["optimize_moves"] + rep["optimize_flips"] >= 0, "the report counts the optimisation")
try:
    topotet.simplify(points, tets, optimize="heavy")
    check(False, "an unknown optimize level is an error")
except ValueError as e:
    check("heavy" in str(e), f"message names the value: {e}")
limited = topotet.simplify(points, tets, materials=materials, fields={"u": field}, ratio=0.05, threads=1,
                           field_weights={"u": 2.0}, max_field_error_rel=1e-6)["report"]
check(limited["rejected"]["field_error"] > 0 and limited["status"] == "stopped_early", f"field limit {limited['rejected']}")
try:
    topotet.simplify(points, tets, fields={"u": field}, field_weights={"pressure": 1.0})
    check(False, "an unknown field weight is an error")
except ValueError as e:
    check("pressure" in str(e), f"message names the field: {e}")

# Limits that would stop the run short relax by default (the report gives the values that hold);
# relax_tolerance=False keeps H as given.
tight = dict(materials=materials, ratio=0.05, threads=1, tolerance_rel=1e-4, feature_angle=180.0)
relaxed = topotet.simplify(points, tets, **tight)["report"]
held = topotet.simplify(points, tets, **tight, relax_tolerance=False, relax_quality=False)["report"]
check(relaxed["relaxations"] and relaxed["tolerance"] > relaxed["tolerance_asked"], f"not relaxed: {relaxed['relaxations']}")
check(relaxed["vertices_after"] < held["vertices_after"] and not held["relaxations"], "relaxing reaches further")
check(held["tolerance"] == held["tolerance_asked"] == relaxed["tolerance_asked"], "a hard H stays as asked")
check(all(s["limit"] in ("tolerance", "min_dihedral", "min_quality") and s["to"] != s["from"] for s in relaxed["relaxations"]),
      f"relaxation steps {relaxed['relaxations']}")

# A target the ball and the pinned box corners cannot reach: the report says what holds the rest.
stuck = topotet.simplify(points, tets, materials=materials, target_vertices=2, threads=1, corners=box_corners)["report"]
check(stuck["status"] == "stopped_early", f"status {stuck['status']}")
why = stuck["stopped"]
check(why is not None and why["vertices"] == stuck["vertices_after"], f"stop census {why}")
check(sum(why["by_reason"].values()) == why["vertices"], "every vertex left has one reason")
check(why["dominant"] in why["by_reason"] and why["by_reason"][why["dominant"]] == max(why["by_reason"].values()),
      f"dominant reason {why['dominant']}")
check(why["pinned_vertices"]["corners"] == len(box_corners), f"pinned {why['pinned_vertices']}")

# The vertex map: total, onto the live output vertices, each input vertex lands near where it was.
vmap = out["vertex_map"]
check(vmap.shape == (len(points),), "map size")
check(vmap.min() >= 0 and vmap.max() < nv, "every input vertex maps to a live output vertex")
check(len(np.unique(vmap)) == nv, "every output vertex is some input vertex")
# Collapses only rename vertices: the output tets are the input tets renamed through the map, less
# those whose four images are not distinct. The flips of the optimisation make new tets, so this
# holds without it; the map is the same with it (it moves no vertex between input ids).
plain = topotet.simplify(points_f32, tets_i32, materials=materials, fields={"u": field}, ratio=0.3, threads=1,
                         corners=box_corners, optimize="none")
check(np.array_equal(plain["vertex_map"], vmap), "the optimisation leaves the vertex map as it is")
renamed = np.sort(vmap[tets], axis=1)
renamed = renamed[(np.diff(renamed, axis=1) != 0).all(axis=1)]
output_tets = np.sort(plain["tets"], axis=1)
check(len(renamed) == len(output_tets), "as many renamed input tets as output tets")
check(np.array_equal(renamed[np.lexsort(renamed.T[::-1])], output_tets[np.lexsort(output_tets.T[::-1])]),
      "the output tets are the input tets renamed through the vertex map")
# The pinned corners map onto themselves.
for corner in box_corners:
    check(np.allclose(out["points"][vmap[corner]], points[corner], atol=1e-6), f"corner {corner} moved")

# Positive volumes: no inverted tet.
p = out["points"][out["tets"]]
vol = np.einsum("ij,ij->i", np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), p[:, 3] - p[:, 0])
check(vol.min() > 0, "an output tet is inverted")

# Same result for every thread count.
again = topotet.simplify(points_f32, tets_i32, materials=materials, fields={"u": field}, ratio=0.3, threads=2,
                         corners=box_corners)
check(np.array_equal(again["points"], out["points"]) and np.array_equal(again["vertex_map"], vmap), "threads")

# read / write round trip.
with tempfile.TemporaryDirectory() as d:
    path = os.path.join(d, "out.mesh")
    topotet.write(path, out)
    back = topotet.read(path)
    check(np.array_equal(back["tets"], out["tets"]) and np.allclose(back["points"], out["points"]), "round trip")
    check(np.array_equal(back["materials"], out["materials"]), "materials round trip")
    check(np.allclose(back["fields"]["u"], out["fields"]["u"]), "field round trip")

# The hierarchy: every collapse recorded into a file; levels read back by vertex count or error; all
# of it is the simplified mesh.
with tempfile.TemporaryDirectory() as d:
    h = os.path.join(d, "h.tth")
    hout = topotet.simplify(points, tets, materials=materials, fields={"u": field}, ratio=0.3, threads=2,
                            hierarchy=h)
    check(hout["vertex_map"] is None and os.path.getsize(h) > 0, "hierarchy written")
    full = topotet.extract(h)
    check(len(full["points"]) == len(hout["points"]) and len(full["tets"]) == len(hout["tets"]),
          "the whole hierarchy is the simplified mesh")
    half = topotet.extract(h, vertices=len(points) // 2)
    check(len(half["points"]) == len(points) // 2, "a level by vertex count")
    check(sorted(np.unique(half["materials"])) == [1, 2], "a level keeps the materials")
    fine = topotet.extract(h, max_error=0.0)
    check(len(half["points"]) >= len(hout["points"]) and len(fine["points"]) >= len(hout["points"]), "levels")
    try:
        topotet.extract(h, vertices=10, max_error=1.0)
        check(False, "vertices and max_error together are an error")
    except ValueError:
        pass

# Errors are ValueErrors with the library's message.
bad = tets.copy()
bad[3, 1] = len(points) + 5
mixed = tets.copy()
mixed[::2] = mixed[::2][:, [0, 2, 1, 3]]  # half inverted: an error (all inverted would be flipped)
for args, needle in [((points, bad), "out of range"), ((points[:, :2], tets), "shape"),
                     ((points, mixed), "tet")]:
    try:
        topotet.simplify(*args)
        check(False, f"no error for {needle}")
    except ValueError as e:
        check(needle in str(e), f"message {e!r} lacks {needle!r}")
try:
    topotet.read("/nonexistent/x.mesh")
    check(False, "no error reading a missing file")
except ValueError as e:
    check("x.mesh" in str(e), f"message {e!r}")
# Cell arrays: carried onto the output tets by overlap volume, each by its kind (topotet/cell_fields.h).
vol = np.abs(np.einsum("ij,ij->i", points[tets[:, 1]] - points[tets[:, 0]],
                       np.cross(points[tets[:, 2]] - points[tets[:, 0]], points[tets[:, 3]] - points[tets[:, 0]]))) / 6.0
mass = vol * 3.0 + (materials == 2) * vol  # density 3 outside, 4 inside
cells = {"density": np.where(materials == 2, 4.0, 3.0), "mass": mass, "region": materials.astype(float) * 10.0,
         "grad": np.stack([centres[:, 0], centres[:, 1]], axis=1)}
cout = topotet.simplify(points, tets, materials=materials, ratio=0.3, threads=1, cell_fields=cells,
                        cell_kinds={"region": "categorical"}, extensive=["mass"])
m_out = len(cout["tets"])
check(list(cout["cell_fields"]) == ["density", "mass", "region", "grad"], f"cell arrays {list(cout['cell_fields'])}")
check(cout["cell_kinds"] == {"density": "intensive", "mass": "extensive", "region": "categorical", "grad": "intensive"},
      f"kinds {cout['cell_kinds']}")
check(cout["cell_fields"]["grad"].shape == (m_out, 2) and cout["cell_fields"]["density"].shape == (m_out,), "cell shapes")
# One material per tet, so a per-material constant stays exact; labels stay labels; the mass is conserved.
expect = np.where(cout["materials"] == 2, 4.0, 3.0)
check(np.allclose(cout["cell_fields"]["density"], expect, rtol=1e-12), "intensive constant per material kept")
check(np.array_equal(cout["cell_fields"]["region"], cout["materials"] * 10.0), "categorical labels kept")
check(abs(cout["cell_fields"]["mass"].sum() - mass.sum()) <= 1e-9 * mass.sum(), "extensive total conserved")
check(cout["cell_remap"]["overlap_pairs"] >= m_out, f"remap report {cout['cell_remap']}")
with tempfile.TemporaryDirectory() as d:
    path = os.path.join(d, "cells.mesh")  # MEDIT keeps the kinds (.sol + names file); 2 components it cannot
    scalar = {k: v for k, v in cout["cell_fields"].items() if k != "grad"}
    topotet.write(path, {**cout, "cell_fields": scalar, "cell_kinds": {k: cout["cell_kinds"][k] for k in scalar}})
    back = topotet.read(path)
    check(np.allclose(back["cell_fields"]["mass"].sum(), cout["cell_fields"]["mass"].sum()), "cell arrays round trip")
    check(back["cell_kinds"]["region"] == "categorical", f"kinds round trip {back['cell_kinds']}")
for bad, needle in (({"density": np.ones(3)}, "number of tets"),):
    try:
        topotet.simplify(points, tets, cell_fields=bad)
        check(False, f"no error for {needle}")
    except ValueError as e:
        check(needle in str(e), f"message {e!r} lacks {needle!r}")
try:
    topotet.simplify(points, tets, cell_fields={"density": cells["density"]}, cell_kinds={"density": "mass"})
    check(False, "no error for an unknown cell kind")
except ValueError as e:
    check("'mass'" in str(e), f"message {e!r}")
# Isosurfaces: embed the level sets, simplify keeping them; their vertices keep the level exactly.
radius = np.sqrt(((points - 3.0) ** 2).sum(axis=1))
embedded = topotet.embed_isosurfaces({"points": points, "tets": tets, "materials": materials,
                                      "fields": {"r": radius}, "cell_fields": {"mass": mass},
                                      "cell_kinds": {"mass": "extensive"}}, ["r=1.7,2.4"])
check(len(embedded["tets"]) > len(tets) and embedded["cell_kinds"] == {"mass": "extensive"}, "cell arrays through embedding")
check(abs(embedded["cell_fields"]["mass"].sum() - mass.sum()) <= 1e-9 * mass.sum(), "embedding shares the mass out")
levels = embedded["isosurfaces"]
check([l["name"] for l in levels] == ["iso:r=1.7", "iso:r=2.4"], f"isosurface names {levels}")
check(all(l["triangles"] > 0 and l["tets_split"] > 0 for l in levels), "isosurfaces embedded")
iso_out = topotet.simplify(embedded["points"], embedded["tets"], materials=embedded["materials"],
                           fields=embedded["fields"], triangles=embedded["triangles"],
                           triangle_refs=embedded["triangle_refs"], ratio=0.3, isosurfaces=levels)
for l in levels:
    on = iso_out["triangles"][iso_out["triangle_refs"] == l["ref"]].ravel()
    check(len(on) > 0 and np.all(iso_out["fields"]["r"].ravel()[on] == l["value"]), f"level {l['name']} exact")
try:
    topotet.embed_isosurfaces({"points": points, "tets": tets}, ["nope=1"])
    check(False, "no error for an unknown isosurface field")
except ValueError as e:
    check("nope" in str(e), f"message {e!r}")
# Out of core from a file: 4 pieces merged back into one, the same topology as an in-core run's
# output (the same counts of vertices and tets per material), the report's levels; a bad size and
# a bad size is a ValueError; a .msh gives the output of its .mesh, with its fields.
with tempfile.TemporaryDirectory() as d:
    big_points, big_tets = grid(12)
    topotet.write(os.path.join(d, "in.mesh"), {"points": big_points, "tets": big_tets,
                                                "fields": {"f": big_points[:, 0] * big_points[:, 1]}})
    rep = topotet.simplify_out_of_core(os.path.join(d, "in.mesh"), os.path.join(d, "out.mesh"), pieces=4,
                                       ratio=0.2, threads=2)
    check(rep["pieces"] == 4 and rep["pieces_left"] == 1 and len(rep["levels"]) == 3, f"out of core levels {rep}")
    ooc_out = topotet.read(os.path.join(d, "out.mesh"))
    check(len(ooc_out["points"]) == rep["vertices_after"] <= 0.2 * len(big_points) + 1, "out of core reached the ratio")
    check(not any(n.startswith(".topotet-scratch") for n in os.listdir(d)), "scratch folder removed")
    corners = ooc_out["points"][ooc_out["tets"]]
    volume = np.abs(np.linalg.det(corners[:, 1:] - corners[:, :1])).sum() / 6.0
    check(np.isclose(volume, 12.0**3, rtol=1e-9), f"out of core keeps the box's volume: {volume}")
    for bad, needle in [({"memory_limit": "lots"}, "memory size"), ({"memory_limit": "1M"}, "memory-limit")]:
        try:
            topotet.simplify_out_of_core(os.path.join(d, "in.mesh"), os.path.join(d, "x.mesh"), **bad)
            check(False, f"no error for {bad}")
        except ValueError as e:
            check(needle in str(e), f"message {e!r} lacks {needle!r}")
    # A .msh streams its node and cell fields.
    topotet.write(os.path.join(d, "fields.msh"), {"points": big_points, "tets": big_tets,
                                                  "fields": {"f": big_points[:, 0]}})
    topotet.simplify_out_of_core(os.path.join(d, "fields.msh"), os.path.join(d, "fields_out.mesh"), pieces=2, ratio=0.3)
    fields_out = topotet.read(os.path.join(d, "fields_out.mesh"))
    check(np.allclose(fields_out["fields"]["f"].ravel(), fields_out["points"][:, 0]),
          "a .msh's node field streams out of core with its vertices")
    topotet.write(os.path.join(d, "cells.msh"), {"points": big_points, "tets": big_tets,
                                                 "cell_fields": {"rho": np.full(len(big_tets), 2.5)}})
    topotet.simplify_out_of_core(os.path.join(d, "cells.msh"), os.path.join(d, "cells_out.mesh"), pieces=2, ratio=0.3)
    cells_out = topotet.read(os.path.join(d, "cells_out.mesh"))
    check(np.allclose(cells_out["cell_fields"]["rho"], 2.5), "a .msh's cell field streams out of core")
    outputs = []
    for name in ("plain.msh", "plain.mesh"):
        topotet.write(os.path.join(d, name), {"points": big_points, "tets": big_tets})
        topotet.simplify_out_of_core(os.path.join(d, name), os.path.join(d, "o_" + name + ".mesh"), pieces=2, ratio=0.3)
        outputs.append(open(os.path.join(d, "o_" + name + ".mesh"), "rb").read())
    check(outputs[0] == outputs[1], "a .msh streams out of core as the same mesh as .mesh")
    # Field error bounds out of core: the limit holds and the report gives the bound (its
    # measurement at every input vertex: tests/unit_out_of_core_field_bounds.cpp).
    fb = topotet.simplify_out_of_core(os.path.join(d, "in.mesh"), os.path.join(d, "fb.mesh"), pieces=4, ratio=0.2,
                                      max_field_error_rel=0.001)
    check(fb["field_bound_rel"] is not None and 0 < fb["field_bound_rel"] <= 0.001 and len(fb["field_bound"]) == 1
          and fb["rejected"]["field_error"] > 0, f"out-of-core field bounds: {fb['field_bound_rel']}")
    check(rep["field_bound"] is None, "no bounds kept, none reported")
    tracked = topotet.simplify(big_points, big_tets, fields={"f": big_points[:, 0] * big_points[:, 1]}, ratio=0.3,
                               field_bounds=True)["report"]
    check(tracked["field_bound_rel"] > 0 and tracked["rejected"]["field_error"] == 0, "field_bounds=True tracks them")
    # The vertex map out of core (a file): without the optimisation's flips the output tets are the
    # input tets renamed through it, less the collapsed ones.
    topotet.simplify_out_of_core(os.path.join(d, "in.mesh"), os.path.join(d, "vm.mesh"), pieces=4, ratio=0.2,
                                 optimize="none", vertex_map=os.path.join(d, "vm.npy"))
    vm = np.load(os.path.join(d, "vm.npy"))
    vm_out = topotet.read(os.path.join(d, "vm.mesh"))
    check(vm.dtype == np.int64 and len(vm) == len(big_points) and vm.min() == 0 and vm.max() == len(vm_out["points"]) - 1,
          f"out-of-core vertex map: {vm.dtype} {len(vm)} entries, {vm.min()}..{vm.max()}")
    renamed = np.sort(vm[big_tets], axis=1)
    renamed = renamed[(np.diff(renamed, axis=1) != 0).all(axis=1)]
    check(sorted(map(tuple, renamed)) == sorted(map(tuple, np.sort(vm_out["tets"], axis=1))),
          "out-of-core vertex map renames the input tets into the output's")
    # A hierarchy file out of core: its coarsest level is the output, a finer one has more points.
    hy = topotet.simplify_out_of_core(os.path.join(d, "in.mesh"), os.path.join(d, "hy.mesh"), pieces=4, ratio=0.2,
                                      hierarchy=os.path.join(d, "hy.tth"))
    hy_out = topotet.read(os.path.join(d, "hy.mesh"))
    coarsest = topotet.extract(os.path.join(d, "hy.tth"), vertices=1)
    check(hy["hierarchy_collapses"] == len(big_points) - len(hy_out["points"]) and hy["hierarchy_bytes"] > 0,
          f"out-of-core hierarchy report: {hy['hierarchy_collapses']} collapses")
    check(sorted(map(tuple, coarsest["points"])) == sorted(map(tuple, hy_out["points"])) and
          len(coarsest["tets"]) == len(hy_out["tets"]), "out-of-core hierarchy: the coarsest level is the output")
    check(len(topotet.extract(os.path.join(d, "hy.tth"), vertices=len(big_points) // 2)["points"]) == len(big_points) // 2,
          "out-of-core hierarchy: a level by vertex count")
    # Pieces kept apart (piece_tets: at most 30% of the tets, so the halves at 30% of their points
    # no longer fit together) are joined by a seam: the target is reached, the box's volume kept.
    sm = topotet.simplify_out_of_core(os.path.join(d, "in.mesh"), os.path.join(d, "seam.mesh"), pieces=2,
                                      piece_tets=len(big_tets) * 3 // 10, ratio=0.3)
    sm_out = topotet.read(os.path.join(d, "seam.mesh"))
    check(sm["levels"][-1]["seams"] == 1 and sm["levels"][-1]["pairs_left_apart"] == 1 and sm["pieces_left"] >= 3,
          f"out-of-core seams: {sm['levels'][-1]}, {sm['pieces_left']} pieces left")
    check(abs(len(sm_out["points"]) - round(0.3 * len(big_points))) <= 0.02 * len(big_points),
          f"out-of-core seams reach the target: {len(sm_out['points'])} of {len(big_points)}")
    corners = sm_out["points"][sm_out["tets"]]
    volume = np.abs(np.linalg.det(corners[:, 1:] - corners[:, :1])).sum() / 6.0
    check(np.isclose(volume, 12.0**3, rtol=1e-9), f"out-of-core seams keep the box's volume: {volume}")
check(topotet.__version__.count(".") == 2, "version")
print(f"python_test: {len(points)} -> {nv} vertices, {len(tets)} -> {len(out['tets'])} tets: pass")
