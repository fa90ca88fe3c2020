"""The ParaView plugin, headless: pvbatch loads it, applies "Simplify (topology-preserving)" to a
real .vtu and saves the result; `topotet check` then compares input and output on its own.

    pvbatch paraview_pvbatch_test.py PLUGIN.so TOPOTET_CLI WORK_DIR

The input is topotet's generated cube-sphere (20k tets, two materials), with the listed surfaces
and polylines of its companion _substructures.vtp moved into the grid as triangle and line cells
(ParaView opens the .vtu alone; a grid is how the filter receives substructures), saved as one
.vtu without a companion, so that `topotet check` reads both meshes the same way.
"""
import os
import subprocess
import sys

from paraview.simple import LoadPlugin, SaveData, XMLUnstructuredGridReader, servermanager
from vtkmodules.vtkCommonCore import vtkIntArray
from vtkmodules.vtkIOXML import vtkXMLPolyDataReader, vtkXMLUnstructuredGridReader, vtkXMLUnstructuredGridWriter

plugin, topotet, work = sys.argv[1:4]
os.makedirs(work, exist_ok=True)
generated = os.path.join(work, "generated.vtu")
source = os.path.join(work, "input.vtu")
result = os.path.join(work, "output.vtu")


def run(*args):
    done = subprocess.run([topotet, *args], capture_output=True, text=True)
    return done.returncode, done.stdout + done.stderr


def single_grid_input():
    """generated.vtu + generated_substructures.vtp -> input.vtu, one grid (refs in "material")."""
    code, text = run("generate", "cube-sphere", "--tets", "20000", "-o", generated)
    assert code == 0, text
    grid_reader = vtkXMLUnstructuredGridReader()
    grid_reader.SetFileName(generated)
    grid_reader.Update()
    grid = grid_reader.GetOutput()
    parts_reader = vtkXMLPolyDataReader()
    parts_reader.SetFileName(generated[:-4] + "_substructures.vtp")
    parts_reader.Update()
    parts = parts_reader.GetOutput()
    # The .vtp holds only the points its cells use: found again in the grid by their coordinates,
    # which both files store as the same doubles.
    index = {grid.GetPoint(i): i for i in range(grid.GetNumberOfPoints())}
    to_grid = [index[parts.GetPoint(i)] for i in range(parts.GetNumberOfPoints())]
    material = grid.GetCellData().GetArray("material")
    refs = parts.GetCellData().GetArray("ref")
    added = {3: 0, 2: 0}
    for c in range(parts.GetNumberOfCells()):
        cell = parts.GetCell(c)
        ids = [to_grid[cell.GetPointId(k)] for k in range(cell.GetNumberOfPoints())]
        assert len(ids) in added, ids
        grid.InsertNextCell(5 if len(ids) == 3 else 3, len(ids), ids)  # VTK_TRIANGLE / VTK_LINE
        material.InsertNextValue(int(refs.GetValue(c)))
        added[len(ids)] += 1
    assert added[3] > 1000 and added[2] > 0, added
    writer = vtkXMLUnstructuredGridWriter()
    writer.SetFileName(source)
    writer.SetInputData(grid)
    assert writer.Write() == 1
    return grid.GetNumberOfPoints()


input_points = single_grid_input()

LoadPlugin(plugin, remote=False, ns=globals())
reader = XMLUnstructuredGridReader(FileName=[source])
simplify = Simplifytopologypreserving(Input=reader)  # noqa: F821 (defined by LoadPlugin)
# The proxy's defaults are the filter's, which are the library's (paraview_filter checks those).
for name in ("TargetRatio", "ToleranceRel", "FeatureAngle", "MinQuality", "MinDihedral", "RelaxLimits", "NumberOfThreads",
             "Verify"):
    shown = simplify.GetProperty(name).GetElement(0)
    real = simplify.GetProperty(name + "Info").GetElement(0)
    assert shown == real, (name, shown, real)
assert abs(simplify.TargetRatio - 0.25) < 1e-12 and abs(simplify.RelativeTolerance - 0.004) < 1e-12
simplify.TargetRatio = 0.2
simplify.UpdatePipeline()
out = servermanager.Fetch(simplify)

fields = out.GetFieldData()
verdict = fields.GetAbstractArray("topotet_topology").GetValue(0)
summary = fields.GetAbstractArray("topotet_summary").GetValue(0)
assert verdict == "PASS", (verdict, summary)
points = out.GetNumberOfPoints()
assert 0.1 * input_points < points <= 0.2 * input_points + 50, (points, input_points, summary)
types = {out.GetCellType(c) for c in range(out.GetNumberOfCells())}
assert types == {10, 5, 3}, types  # tets, and the surfaces and polylines carried through
material = out.GetCellData().GetArray("material")
assert material is not None
tet_materials = {int(material.GetValue(c)) for c in range(out.GetNumberOfCells()) if out.GetCellType(c) == 10}
assert len(tet_materials) == 2, tet_materials

SaveData(result, proxy=simplify)
code, text = run("check", source, result)
print(text)
assert code == 0 and "topology  PASS" in text, text
print("paraview_pvbatch: %d -> %d vertices, %s" % (input_points, points, summary))
