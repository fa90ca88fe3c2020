"""topotet on a vtkUnstructuredGrid (VTK 9, Debian: python3-vtk9), through numpy without a copy of
the grid's arrays where their types allow it (vtkmodules.util.numpy_support).

    import topotet.vtk
    out = topotet.vtk.simplify(ugrid, ratio=0.1)          # a new vtkUnstructuredGrid
    out = topotet.vtk.simplify(ugrid, ratio=0.1, material_array="ObjectId", extensive=["mass"])

The grid's tets are simplified; other volume cells are an error, as on the command line, unless
tets_only=True leaves them out with a warning (--tets-only); its other cells (triangles, lines,
vertices) are ignored: listed surfaces
and polylines come from files (topotet.read) or from simplify()'s triangles / segments. The material
of each tet is the integer cell array `material_array`, or the first of
topotet._meshio.MATERIAL_ARRAYS the grid has, else 0. Every point array becomes a field and comes
back as a point array; every other numeric cell array is carried onto the new tets (integer arrays
as labels, float arrays by volume-weighted average, `extensive` names as conserved sums:
topotet/cell_fields.h) and comes back as a cell array of the same name and type. simplify()'s
report is in the output's field data as "topotet_report" (a JSON string).
"""
import json

import numpy as np

from ._meshio import MATERIAL_ARRAYS, cell_arguments, other_volume_cells

VTK_TETRA = 10
VTK_VOLUME_CELLS = {11: "voxel", 12: "hexahedron", 13: "wedge", 14: "pyramid", 24: "quadratic tetra",
                    25: "quadratic hexahedron", 42: "polyhedron"}


def _numpy(array):
    from vtkmodules.util.numpy_support import vtk_to_numpy

    return vtk_to_numpy(array)


def simplify(ugrid, material_array=None, extensive=(), tets_only=False, **options):
    """A new vtkUnstructuredGrid: `ugrid`'s tets simplified by topotet.simplify(**options)."""
    from vtkmodules.util.numpy_support import numpy_to_vtk
    from vtkmodules.vtkCommonCore import vtkPoints, vtkStringArray
    from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkUnstructuredGrid

    from ._core import simplify as simplify_arrays

    if ugrid.GetNumberOfPoints() == 0:
        raise ValueError("the grid has no points")
    types = _numpy(ugrid.GetCellTypesArray()) if ugrid.GetNumberOfCells() else np.zeros(0, np.uint8)
    is_tet = types == VTK_TETRA
    if not is_tet.any():
        raise ValueError("the grid has no tetrahedra (VTK_TETRA cells): topotet simplifies tetrahedral meshes")
    other_volume_cells({VTK_VOLUME_CELLS[t]: int((types == t).sum()) for t in np.unique(types) if t in VTK_VOLUME_CELLS},
                       tets_only)
    cells = ugrid.GetCells()
    offsets = _numpy(cells.GetOffsetsArray())
    connectivity = _numpy(cells.GetConnectivityArray())
    starts = offsets[:-1][is_tet]
    tets = connectivity[starts[:, None] + np.arange(4)]
    points = _numpy(ugrid.GetPoints().GetData())

    cell_data = ugrid.GetCellData()
    names = [cell_data.GetArrayName(i) for i in range(cell_data.GetNumberOfArrays()) if cell_data.GetArray(i) is not None]
    arrays = {name: _numpy(cell_data.GetArray(name)) for name in names}
    if material_array is not None and material_array not in arrays:
        raise ValueError(f"material_array {material_array!r}: the grid has no cell array of that name "
                         f"(its cell arrays: {names or 'none'})")
    material = material_array or next((n for n in MATERIAL_ARRAYS if n in arrays and np.issubdtype(arrays[n].dtype, np.integer)), None)
    kwargs = {}
    if material is not None:
        kwargs["materials"] = arrays[material][is_tet].astype(np.int32)
    dtypes = {name: values.dtype for name, values in arrays.items() if name != material}
    kwargs.update(cell_arguments({name: arrays[name][is_tet] for name in dtypes}, extensive, "the grid has"))
    point_data = ugrid.GetPointData()
    fields = {}
    for i in range(point_data.GetNumberOfArrays()):
        array = point_data.GetArray(i)
        if array is not None and array.GetName():
            fields[array.GetName()] = _numpy(array)
    if fields:
        kwargs["fields"] = fields
    result = simplify_arrays(points, tets, **kwargs, **options)

    out = vtkUnstructuredGrid()
    vtk_points = vtkPoints()
    vtk_points.SetData(numpy_to_vtk(np.ascontiguousarray(result["points"]), deep=True))
    out.SetPoints(vtk_points)
    new_tets = np.ascontiguousarray(result["tets"], dtype=np.int64)
    cell_array = vtkCellArray()
    cell_array.SetData(numpy_to_vtk(np.arange(0, 4 * len(new_tets) + 1, 4, dtype=np.int64), deep=True),
                       numpy_to_vtk(new_tets.ravel(), deep=True))
    out.SetCells(VTK_TETRA, cell_array)
    for name, values in result["fields"].items():
        array = numpy_to_vtk(np.ascontiguousarray(values), deep=True)
        array.SetName(name)
        out.GetPointData().AddArray(array)
    material_values = [(material or "material", np.asarray(result["materials"]),
                        arrays[material].dtype if material is not None else np.dtype(np.int32))]
    for name, values in result["cell_fields"].items():
        values = np.asarray(values)
        if result["cell_kinds"].get(name) == "categorical" or np.issubdtype(dtypes.get(name, np.float64), np.integer):
            values = np.rint(values)
        material_values.append((name, values, dtypes.get(name, np.dtype(np.float64))))
    for name, values, dtype in material_values:
        array = numpy_to_vtk(np.ascontiguousarray(values.astype(dtype)), deep=True)
        array.SetName(name)
        out.GetCellData().AddArray(array)
    report = vtkStringArray()
    report.SetName("topotet_report")
    report.InsertNextValue(json.dumps(result["report"], default=str))
    out.GetFieldData().AddArray(report)
    return out
