"""Checks the layering of the source tree: every quoted #include resolves to a file of the tree,
and runs from a folder to the same folder or to one on a lower floor, never up and never sideways.

The floors are the architecture (docs/architecture.md); a change to them is a change here.
Usage: layering.py REPO_ROOT. Exits 1 and names every offending include."""
import os
import re
import sys

root = sys.argv[1]
# Lowest first. Folders on one floor may not include each other. A library's public headers
# (X/include) stand on X's floor, but for the engine's, the public types the engine is built on.
FLOORS = [
    ["parallel"],
    ["engine/include"],  # the engine's public types: every floor above builds on them
    ["engine/mesh"],
    ["engine/guarantees", "engine/hierarchy", "engine/cell_data", "engine/isosurface"],
    ["engine/kernel"],
    ["engine/cost", "engine/features"],
    ["engine"],  # the drivers
    ["io", "generate"],
    ["metrics", "outofcore"],  # outofcore/: meshes larger than memory, on the drivers and io
    ["capi", "python", "mpi"],
    ["cli", "paraview"],  # paraview/: the ParaView plugin, built in a tree of its own (docs/paraview.md)
    ["bench", "tests", "examples"],
]
rank = {folder: i for i, floor in enumerate(FLOORS) for folder in floor}
# Where a quoted include is looked up, in order (the include directories the build gives).
SEARCH = ["", "engine", "engine/include", "io/include", "io/vtk/include", "generate/include", "metrics/include",
          "capi/include", "mpi/include", "mpi", "outofcore/include", "paraview/filter"]  # mpi: topotet-mpi sees exchange.h


def folder_of(path):
    """The longest folder of FLOORS that holds path."""
    best = None
    for folder in rank:
        if path == folder or path.startswith(folder + "/"):
            if best is None or len(folder) > len(best):
                best = folder
    return best


include = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)
failures, checked = [], 0
for dirpath, dirnames, filenames in os.walk(root):
    rel_dir = os.path.relpath(dirpath, root)
    dirnames[:] = [d for d in dirnames if not d.startswith(".") and not d.startswith("build")]
    for name in filenames:
        if not name.endswith((".h", ".cpp", ".c", ".cxx")):  # .cxx: VTK classes (paraview/)
            continue
        src = os.path.normpath(os.path.join(rel_dir, name))
        here = folder_of(src)
        if here is None:
            continue
        text = open(os.path.join(root, src), errors="replace").read()
        for target in include.findall(text):
            candidates = [os.path.normpath(os.path.join(rel_dir, target))] + \
                         [os.path.normpath(os.path.join(d, target)) for d in SEARCH]
            found = next((c for c in candidates if os.path.isfile(os.path.join(root, c))), None)
            if found is None:
                continue  # generated (version.h) or a system header written with quotes
            there = folder_of(found)
            checked += 1
            if there is None or there == here:
                continue
            if rank[there] > rank[here]:
                failures.append(f"{src}: includes {found} ({there}/ is above {here}/)")
            elif rank[there] == rank[here]:
                failures.append(f"{src}: includes {found} ({there}/ and {here}/ are on one floor)")
for f in failures:
    print(f)
print(f"{checked} includes checked, {len(failures)} running up or sideways")
sys.exit(1 if failures else 0)
