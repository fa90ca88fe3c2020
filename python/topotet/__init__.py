"""topotet: topology-preserving simplification of tetrahedral meshes, numpy arrays in and out.

    import topotet
    out = topotet.simplify(points, tets, materials=materials, ratio=0.1)   # every default the library's
    mesh = topotet.read("in.mesh"); topotet.write("out.msh", out)

Everything of the extension (`topotet._core`, python/topotet_module.cpp) is here, plus:
- meshio: `from_meshio(mesh)` gives simplify()'s keyword arguments, `to_meshio(result)` a meshio.Mesh,
  `simplify_meshio(mesh, **options)` both (point and cell data carried);
- VTK: `topotet.vtk.simplify(ugrid, **options)` on a vtkUnstructuredGrid (topotet/vtk.py);
- `python -m topotet simplify IN -o OUT ...`, the command line's main options (topotet/__main__.py).
meshio and VTK are imported only when those functions are called.
"""
from ._core import *  # noqa: F401,F403 (the extension's functions are the package's)
from ._core import __version__  # noqa: F401
from ._meshio import from_meshio, simplify_meshio, to_meshio  # noqa: F401
