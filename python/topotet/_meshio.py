"""meshio 7 meshes in and out of topotet.simplify (Debian: python3-meshio).

A meshio.Mesh maps onto simplify()'s keywords as follows:
- points -> points; "tetra" cells -> tets; other volume cells are an error, as on the command line,
  unless tets_only=True leaves them out with a warning (--tets-only);
- the material of each tet: the integer cell array `material_array`, or the first of MATERIAL_ARRAYS
  that the mesh has; none: every tet is material 0;
- "triangle" cells with an integer ref array (the same names) -> listed surfaces (triangles,
  triangle_refs); "line" cells likewise -> polylines (segments, segment_refs);
- point_data -> fields (float arrays of one value or one row per point), except meshio's own
  "medit:" and "gmsh:" arrays (vertex refs, dim tags);
- the tets' other cell_data -> cell_fields: integer arrays are "categorical" (labels: the majority of
  the volume), float arrays "intensive" (volume-weighted average); `extensive` names the amounts to
  conserve as sums (topotet/cell_fields.h).
to_meshio() gives back points, tetra cells, the material array (under the name it came in, else
"material"), the listed triangles and lines with their refs, every field as point_data and every
cell field as cell_data of the tets.
"""
import warnings

import numpy as np

MATERIAL_ARRAYS = ("material", "gmsh:physical", "medit:ref", "ObjectId", "ElementBlockIds", "CellEntityIds")
FORMAT_ARRAYS = ("medit:", "gmsh:")
VOLUME_CELLS = ("hexahedron", "wedge", "pyramid", "polyhedron", "tetra10", "hexahedron20", "hexahedron27",
                "wedge15", "pyramid13")


def _blocks(mesh, cell_type):
    return [i for i, block in enumerate(mesh.cells) if block.type == cell_type]


def _material_name(mesh, material_array, tetra):
    if material_array is not None:
        if material_array not in mesh.cell_data:
            raise ValueError(f"material_array {material_array!r}: the mesh has no cell array of that name "
                             f"(its cell arrays: {sorted(mesh.cell_data) or 'none'})")
        return material_array
    for name in MATERIAL_ARRAYS:
        if name in mesh.cell_data and all(np.issubdtype(np.asarray(mesh.cell_data[name][i]).dtype, np.integer)
                                          for i in tetra):
            return name
    return None


def _gather(mesh, name, blocks):
    return np.concatenate([np.asarray(mesh.cell_data[name][i]) for i in blocks]) if blocks else np.zeros(0)


def cell_arguments(arrays, extensive, where):
    """simplify()'s cell_fields and cell_kinds for the tets' numeric arrays {name: values}: integer
    arrays are labels ("categorical"), float arrays "intensive", the names in `extensive` amounts to
    conserve. `where` names the owner in the error for an unknown extensive name."""
    cell_fields, kinds = {}, {}
    for name, values in arrays.items():
        if not np.issubdtype(values.dtype, np.number):
            continue
        cell_fields[name] = values.astype(np.float64)
        kinds[name] = "categorical" if np.issubdtype(values.dtype, np.integer) else "intensive"
    for name in extensive:
        if name not in cell_fields:
            raise ValueError(f"extensive {name!r}: {where} no cell array of that name")
        kinds[name] = "extensive"
    return ({"cell_fields": cell_fields, "cell_kinds": kinds} if cell_fields else {})


def other_volume_cells(counts, tets_only):
    """Refuses a mixed mesh ({cell type: count} of its non-tet volume cells) as the command line
    does, or with tets_only warns that they are left out (--tets-only)."""
    if not counts:
        return
    if not tets_only:
        raise ValueError(f"the mesh has other volume cells than tets ({counts}): pass tets_only=True to leave "
                         "them out (the command line's --tets-only)")
    warnings.warn(f"tets_only: left out {counts}; the output covers the tets only", stacklevel=3)


def from_meshio(mesh, material_array=None, extensive=(), tets_only=False):
    """simplify()'s keyword arguments for a meshio.Mesh (see the module's doc for the mapping):
    topotet.simplify(**topotet.from_meshio(mesh), ratio=0.1)."""
    return _arguments(mesh, material_array, extensive, tets_only)[0]


def _arguments(mesh, material_array, extensive, tets_only):
    tetra = _blocks(mesh, "tetra")
    if not tetra:
        raise ValueError("the mesh has no 'tetra' cells: topotet simplifies tetrahedral meshes")
    counts = {}
    for b in mesh.cells:
        if b.type in VOLUME_CELLS:
            counts[b.type] = counts.get(b.type, 0) + len(b.data)
    other_volume_cells(counts, tets_only)
    tets = np.concatenate([np.asarray(mesh.cells[i].data) for i in tetra])
    kwargs = {"points": np.asarray(mesh.points, dtype=np.float64)[:, :3], "tets": tets}
    material = _material_name(mesh, material_array, tetra)
    if material is not None:
        kwargs["materials"] = _gather(mesh, material, tetra).astype(np.int32)
    for cell_type, cells_key, refs_key in (("triangle", "triangles", "triangle_refs"), ("line", "segments", "segment_refs")):
        blocks = _blocks(mesh, cell_type)
        if not blocks:
            continue
        kwargs[cells_key] = np.concatenate([np.asarray(mesh.cells[i].data) for i in blocks])
        ref = next((n for n in ((material,) if material else ()) + MATERIAL_ARRAYS if n in mesh.cell_data), None)
        refs = _gather(mesh, ref, blocks) if ref else np.ones(len(kwargs[cells_key]))
        kwargs[refs_key] = refs.astype(np.int32)
    # meshio's own bookkeeping (medit:ref vertex labels, gmsh:dim_tags) is not a field to steer the cost.
    fields = {name: np.asarray(v, dtype=np.float64) for name, v in mesh.point_data.items()
              if not name.startswith(FORMAT_ARRAYS)}
    if fields:
        kwargs["fields"] = fields
    arrays = {name: _gather(mesh, name, tetra) for name in mesh.cell_data if name != material}
    kwargs.update(cell_arguments(arrays, extensive, "the tets have"))
    return kwargs, material


def to_meshio(result, material_array="material"):
    """A meshio.Mesh of a simplify() result (or of a read() mesh dict)."""
    import meshio

    cells = [("tetra", np.asarray(result["tets"]))]
    cell_data = {material_array: [np.asarray(result["materials"])]}
    for name, values in result.get("cell_fields", {}).items():
        kind = result.get("cell_kinds", {}).get(name)
        values = np.asarray(values)
        cell_data[name] = [np.rint(values).astype(np.int64) if kind == "categorical" else values]
    for key, refs_key, cell_type in (("triangles", "triangle_refs", "triangle"), ("segments", "segment_refs", "line")):
        items = np.asarray(result.get(key, np.zeros((0, 0))))
        if len(items):
            cells.append((cell_type, items))
            for name in cell_data:  # every cell array needs a value per block
                cell_data[name].append(np.asarray(result[refs_key]) if name == material_array
                                       else np.zeros((len(items),) + cell_data[name][0].shape[1:], cell_data[name][0].dtype))
    return meshio.Mesh(np.asarray(result["points"]), cells, point_data=dict(result.get("fields", {})), cell_data=cell_data)


def simplify_meshio(mesh, material_array=None, extensive=(), tets_only=False, **options):
    """topotet.simplify on a meshio.Mesh: (the simplified meshio.Mesh, simplify()'s report). The
    material array keeps its name; every point and cell array of the tets is carried."""
    from ._core import simplify

    kwargs, material = _arguments(mesh, material_array, extensive, tets_only)
    result = simplify(**kwargs, **options)
    return to_meshio(result, material_array=material or "material"), result["report"]
