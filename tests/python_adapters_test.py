"""The Python package beyond the extension: the meshio adapters, topotet.vtk.simplify on a
vtkUnstructuredGrid, `python -m topotet`, and simplify()'s keyword defaults against the library's.

A 4x4x4 grid of cubes (6 tets each), two materials (x < 2 and x > 2), a point field, and three cell
arrays: density, constant per material (intensive: stays that constant to rounding), label =
material x 10 (an integer array: categorical, must equal the output's material x 10) and mass
(extensive: its sum is conserved). Run with PYTHONPATH=<build>/python (ctest sets it).
"""
import json
import os
import re
import subprocess
import sys
import tempfile

import numpy as np

import topotet

failures = []


def check(cond, what):
    if not cond:
        failures.append(what)
        print("FAIL:", what)


def grid():
    n = 4
    points = np.stack(np.meshgrid(*[np.arange(n + 1.0)] * 3, indexing="ij"), axis=-1).reshape(-1, 3)
    vid = lambda i, j, k: (i * (n + 1) + j) * (n + 1) + k
    tets = []
    for i in range(n):
        for j in range(n):
            for k in range(n):
                c = [vid(i + a, j + b, k + d) for a in (0, 1) for b in (0, 1) for d in (0, 1)]
                for t in ((0, 1, 3, 7), (0, 3, 2, 7), (0, 2, 6, 7), (0, 6, 4, 7), (0, 4, 5, 7), (0, 5, 1, 7)):
                    tets.append([c[x] for x in t])
    tets = np.array(tets, dtype=np.int64)
    p = points[tets]
    vol = np.einsum("ij,ij->i", np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), p[:, 3] - p[:, 0])
    tets[vol < 0] = tets[vol < 0][:, [0, 2, 1, 3]]
    materials = np.where(p[:, :, 0].mean(axis=1) < 2, 1, 2).astype(np.int32)
    f = points[:, 0] * 0.5 + points[:, 1] ** 2
    density = np.where(materials == 1, 7.85, 2.7)
    label = (materials * 10).astype(np.int64)
    mass = 1.0 + np.arange(len(tets)) % 5
    return points, tets, materials, f, density, label, mass


def check_cells(name, materials, density, label, mass, mass_before, n_tets_before):
    check(0 < len(materials) < n_tets_before, f"{name}: {len(materials)} tets out of {n_tets_before}")
    check(sorted(set(int(m) for m in materials)) == [1, 2], f"{name}: materials {sorted(set(materials))}")
    want = np.where(np.asarray(materials) == 1, 7.85, 2.7)
    check(np.allclose(density, want, rtol=1e-13, atol=0), f"{name}: density not constant per material")
    check(np.array_equal(np.asarray(label).astype(np.int64), np.asarray(materials).astype(np.int64) * 10),
          f"{name}: label != material x 10")
    check(abs(float(np.sum(mass)) - mass_before) <= 1e-9 * mass_before, f"{name}: mass {mass_before} -> {np.sum(mass)}")


points, tets, materials, f, density, label, mass = grid()
mass_before = float(mass.sum())

# simplify()'s keyword defaults are the library's (they once drifted: tolerance_rel was 0 here).
defaults = topotet.default_options()
signature = topotet.simplify.__doc__.splitlines()[0]
kw = dict(re.findall(r"(\w+): [^=,]+ = ('[^']*'|[-\w.]+)", signature))
for key, value in defaults.items():
    check(key in kw, f"simplify() has no keyword {key}")
    if key in kw:
        if isinstance(value, bool):
            given = kw[key] == "True"
        elif isinstance(value, str):
            given = kw[key].strip("'")
        else:
            given = type(value)(float(kw[key]))
        check(given == value, f"simplify({key}=...) defaults to {kw[key]}, the library to {value}")

# --- meshio
try:
    import meshio
except ImportError:
    meshio = None
    print("meshio not importable (Debian: python3-meshio): the meshio adapters are not tested")
if meshio is not None:
    mesh = meshio.Mesh(points, [("tetra", tets)], point_data={"f": f},
                       cell_data={"material": [materials], "density": [density], "label": [label], "mass": [mass]})
    kwargs = topotet.from_meshio(mesh, extensive=["mass"])
    check(kwargs["cell_kinds"] == {"density": "intensive", "label": "categorical", "mass": "extensive"},
          f"from_meshio kinds {kwargs['cell_kinds']}")
    check(np.array_equal(kwargs["materials"], materials), "from_meshio: materials from 'material'")
    out, report = topotet.simplify_meshio(mesh, extensive=["mass"], ratio=0.3, threads=2)
    check(report["status"] in ("ok", "stopped_early"), f"meshio status {report['status']}")
    cd = {k: v[0] for k, v in out.cell_data.items()}
    check_cells("meshio", cd["material"], cd["density"], cd["label"], cd["mass"], mass_before, len(tets))
    check(np.issubdtype(cd["label"].dtype, np.integer), "meshio: label stays an integer array")
    check(out.point_data["f"].shape == (len(out.points),), "meshio: the point field comes back, one value a point")
    out1, _ = topotet.simplify_meshio(mesh, extensive=["mass"], ratio=0.3, threads=1)
    check(np.array_equal(out.points, out1.points) and np.array_equal(out.cells[0].data, out1.cells[0].data),
          "meshio: 1 and 2 threads give the same mesh")
    # A mesher's file as meshio reads it (Mmg's tinyBoxt, ../shared/data when this checkout has it):
    # its triangles and ridges with their refs become listed surfaces and polylines, medit:ref the
    # materials, and meshio's own vertex refs no field.
    tiny = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "shared", "data", "mmg", "tinyBoxt.mesh")
    if os.path.exists(tiny):
        k = topotet.from_meshio(meshio.read(tiny))
        check(len(k["triangles"]) == len(k["triangle_refs"]) > 0 and len(k["segments"]) > 0 and "fields" not in k,
              f"tinyBoxt through meshio: {sorted(k)}")
        check(sorted(set(k["materials"].tolist())) == [2, 3], "tinyBoxt through meshio: its two materials (refs 2 and 3)")
    # Binary MEDIT (.meshb) both ways with meshio's own, independent GMF code: the same tets,
    # materials and points.
    with tempfile.TemporaryDirectory() as d:
        ours = os.path.join(d, "ours.meshb")
        topotet.write(ours, {"points": points, "tets": tets, "materials": materials})
        theirs = meshio.read(ours)
        check(np.array_equal(theirs.points, points) and np.array_equal(theirs.cells_dict["tetra"], tets) and
              np.array_equal(theirs.cell_data_dict["medit:ref"]["tetra"], materials), "meshio reads topotet's .meshb")
        meshio.write(os.path.join(d, "theirs.meshb"), meshio.Mesh(points, [("tetra", tets)],
                                                                  cell_data={"medit:ref": [materials]}))
        back = topotet.read(os.path.join(d, "theirs.meshb"))
        check(np.array_equal(back["points"], points) and np.array_equal(back["tets"], tets) and
              np.array_equal(back["materials"], materials), "topotet reads meshio's .meshb")
    try:
        topotet.from_meshio(mesh, material_array="nope")
        check(False, "an unknown material_array is an error")
    except ValueError as e:
        check("nope" in str(e) and "density" in str(e), f"material_array error names it and the arrays: {e}")
    # A mixed mesh is refused as on the command line, or its tets taken with tets_only (a warning).
    hexes = np.array([[0, 1, 6, 5, 25, 26, 31, 30]])
    mixed = meshio.Mesh(points, [("tetra", tets), ("hexahedron", hexes)],
                        cell_data={"material": [materials, np.array([1], dtype=np.int32)]})
    try:
        topotet.from_meshio(mixed)
        check(False, "a mixed mesh is refused without tets_only")
    except ValueError as e:
        check("hexahedron" in str(e) and "tets_only" in str(e), f"mixed mesh: {e}")
    import warnings
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        k = topotet.from_meshio(mixed, tets_only=True)
    check(len(k["tets"]) == len(tets) and any("left out" in str(w.message) for w in caught),
          "tets_only: the tets taken, the hexahedron left out with a warning")
    try:
        topotet.from_meshio(meshio.Mesh(points, [("triangle", tets[:, :3])]))
        check(False, "a mesh without tets is an error")
    except ValueError as e:
        check("tetra" in str(e), f"no tets: {e}")

# --- VTK
try:
    from vtkmodules.util.numpy_support import numpy_to_vtk
    from vtkmodules.vtkCommonCore import vtkPoints
    from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkUnstructuredGrid
    import topotet.vtk
except ImportError:
    numpy_to_vtk = None
    print("VTK not importable (Debian: python3-vtk9): topotet.vtk is not tested")
if numpy_to_vtk is not None:
    ugrid = vtkUnstructuredGrid()
    vp = vtkPoints()
    vp.SetData(numpy_to_vtk(points, deep=True))
    ugrid.SetPoints(vp)
    cells = vtkCellArray()
    cells.SetData(numpy_to_vtk(np.arange(0, 4 * len(tets) + 1, 4, dtype=np.int64), deep=True),
                  numpy_to_vtk(tets.ravel(), deep=True))
    ugrid.SetCells(10, cells)
    for name, values, data in (("f", f, ugrid.GetPointData()), ("ObjectId", materials, ugrid.GetCellData()),
                               ("density", density, ugrid.GetCellData()), ("label", label, ugrid.GetCellData()),
                               ("mass", mass, ugrid.GetCellData())):
        a = numpy_to_vtk(values, deep=True)
        a.SetName(name)
        data.AddArray(a)
    result = topotet.vtk.simplify(ugrid, ratio=0.3, threads=2, extensive=["mass"])
    from vtkmodules.util.numpy_support import vtk_to_numpy
    got = {n: vtk_to_numpy(result.GetCellData().GetArray(n)) for n in ("ObjectId", "density", "label", "mass")}
    check(result.GetNumberOfCells() == len(got["ObjectId"]), "vtk: one material per output tet")
    check_cells("vtk", got["ObjectId"], got["density"], got["label"], got["mass"], mass_before, len(tets))
    check(result.GetCellData().GetArray("label").GetDataType() == ugrid.GetCellData().GetArray("label").GetDataType(),
          "vtk: label keeps its VTK type")
    check(result.GetPointData().GetArray("f").GetNumberOfTuples() == result.GetNumberOfPoints(), "vtk: point field back")
    report = json.loads(result.GetFieldData().GetAbstractArray("topotet_report").GetValue(0))
    check(report["status"] in ("ok", "stopped_early") and report["tolerance"] > 0, f"vtk: report {report.get('status')}")
    # From a file, as ParaView writes one: VTK's own .vtu writer, then VTK's reader and meshio's.
    from vtkmodules.vtkIOXML import vtkXMLUnstructuredGridReader, vtkXMLUnstructuredGridWriter
    vtu = os.path.join(tempfile.mkdtemp(prefix="topotet_vtu_"), "grid.vtu")
    writer = vtkXMLUnstructuredGridWriter()
    writer.SetFileName(vtu)
    writer.SetInputData(ugrid)
    check(writer.Write() == 1, "vtk: the .vtu written")
    reader = vtkXMLUnstructuredGridReader()
    reader.SetFileName(vtu)
    reader.Update()
    from_file = topotet.vtk.simplify(reader.GetOutput(), ratio=0.3, threads=1, extensive=["mass"])
    check(np.array_equal(vtk_to_numpy(from_file.GetCells().GetConnectivityArray()),
                         vtk_to_numpy(result.GetCells().GetConnectivityArray())),
          "vtk: the grid read from its .vtu gives the same mesh (1 thread against 2)")
    if meshio is not None:
        m, _ = topotet.simplify_meshio(meshio.read(vtu), ratio=0.3, extensive=["mass"], material_array="ObjectId")
        cd = {k: v[0] for k, v in m.cell_data.items()}
        check_cells("meshio from .vtu", cd["ObjectId"], cd["density"], cd["label"], cd["mass"], mass_before, len(tets))
    try:
        topotet.vtk.simplify(ugrid, material_array="nope")
        check(False, "vtk: an unknown material_array is an error")
    except ValueError as e:
        check("nope" in str(e), f"vtk: material_array error: {e}")

# --- python -m topotet
work = tempfile.mkdtemp(prefix="topotet_pym_")
src = os.path.join(work, "in.mesh")
topotet.write(src, {"points": points, "tets": tets, "materials": materials, "fields": {"f": f},
                    "cell_fields": {"density": density, "label": label.astype(float), "mass": mass},
                    "cell_kinds": {"density": "intensive", "label": "categorical", "mass": "intensive"}})
dst = os.path.join(work, "out.mesh")
env = dict(os.environ)


def pym(*args):
    return subprocess.run([sys.executable, "-m", "topotet", *args], capture_output=True, text=True, env=env)


run = pym("simplify", src, "-o", dst, "--ratio", "0.3", "--extensive", "mass", "--threads", "2")
check(run.returncode == 0, f"python -m topotet simplify: {run.returncode} {run.stderr}")
check("collapses/s" in run.stdout and "status    ok" in run.stdout, f"python -m report: {run.stdout}")
if run.returncode == 0:
    back = topotet.read(dst)
    cf = back["cell_fields"]
    check_cells("python -m", back["materials"], cf["density"], cf["label"], cf["mass"], mass_before, len(tets))
    direct = topotet.simplify(points, tets, materials=materials, fields={"f": f}, ratio=0.3, threads=1)
    check(np.array_equal(back["tets"], direct["tets"]), "python -m gives simplify()'s own mesh (the same defaults)")
run = pym("simplify", src, "-o", dst, "--ratio", "0.3", "--field-bounds")
check(run.returncode == 0 and "bounds    field error bound" in run.stdout, f"python -m --field-bounds: {run.stdout} {run.stderr}")
# --vertex-map: the file holds simplify()'s own map (read back with read_vertex_map and numpy.load).
run = pym("simplify", src, "-o", dst, "--ratio", "0.3", "--vertex-map", os.path.join(work, "map.npy"), "-q")
check(run.returncode == 0, f"python -m topotet simplify --vertex-map: {run.returncode} {run.stderr}")
if run.returncode == 0:
    direct = topotet.simplify(points, tets, materials=materials, fields={"f": f}, ratio=0.3)
    written = np.load(os.path.join(work, "map.npy"))
    check(np.array_equal(written, direct["vertex_map"]) and np.array_equal(topotet.read_vertex_map(os.path.join(work, "map.npy")), written),
          "python -m --vertex-map writes simplify()'s vertex map")
    topotet.write_vertex_map(os.path.join(work, "map.txt"), direct["vertex_map"])
    check(np.array_equal(np.loadtxt(os.path.join(work, "map.txt"), dtype=np.int64), direct["vertex_map"]), "write_vertex_map .txt")
run = pym("simplify", os.path.join(work, "missing.mesh"), "-o", dst)
check(run.returncode == 2 and "topotet: error:" in run.stderr and "missing.mesh" in run.stderr,
      f"a missing file: {run.returncode} {run.stderr}")
run = pym("simplify", src, "-o", dst, "--extensive", "nope")
check(run.returncode == 2 and "nope" in run.stderr, f"an unknown cell array: {run.returncode} {run.stderr}")
run = pym("info", src)
check(run.returncode == 0 and "cell arrays density (intensive), label (categorical), mass (intensive)" in run.stdout,
      f"python -m topotet info: {run.stdout} {run.stderr}")

if failures:
    sys.exit(f"python_adapters_test: {len(failures)} failed")
print("python_adapters_test: meshio, vtk, python -m topotet and the defaults: pass")
