"""Checks a partitioned output of topotet-mpi against the gathered output of the same run.

    python3 tests/mpi_pvtu_check.py OUT.pvtu GATHERED.mesh RANKS

Reads the .pvtu and each .vtu piece it names (inline base64 arrays, as topotet writes them), and
checks: one piece per rank, each with tets, a material per tet and the fields of the gathered mesh
plus global_id per point; the pieces' tets add up to the gathered mesh's tets, and their distinct
global ids to its vertices. Prints one line per failed check; exits 1 on any.
"""
import base64
import os
import struct
import sys
import xml.etree.ElementTree as ET


def medit_counts(path):
    """Vertex and tet counts of a MEDIT .mesh (keywords on their own lines, count on the next)."""
    counts = {}
    with open(path) as f:
        lines = [l.strip() for l in f]
    for i, l in enumerate(lines):
        if l in ("Vertices", "Tetrahedra") and i + 1 < len(lines):
            counts[l] = int(lines[i + 1].split()[0])
    return counts.get("Vertices", 0), counts.get("Tetrahedra", 0)


def decode(array):
    raw = base64.b64decode("".join(array.text.split()))
    size = struct.unpack("<Q", raw[:8])[0]
    fmt = {"Float64": "d", "Int32": "i", "Int64": "q", "UInt8": "B"}[array.get("type")]
    return struct.unpack("<%d%s" % (size // struct.calcsize(fmt), fmt), raw[8:8 + size])


def main():
    pvtu, gathered, ranks = sys.argv[1], sys.argv[2], int(sys.argv[3])
    errors = []
    root = ET.parse(pvtu).getroot()
    grid = root.find("PUnstructuredGrid")
    pieces = [p.get("Source") for p in grid.findall("Piece")]
    point_arrays = [a.get("Name") for a in grid.find("PPointData").findall("PDataArray")]
    if len(pieces) != ranks:
        errors.append("%d pieces for %d ranks" % (len(pieces), ranks))
    tets, ids = 0, set()
    for source in pieces:
        path = os.path.join(os.path.dirname(pvtu), source)
        piece = ET.parse(path).getroot().find("UnstructuredGrid").find("Piece")
        n_points, n_cells = int(piece.get("NumberOfPoints")), int(piece.get("NumberOfCells"))
        arrays = {a.get("Name"): decode(a) for a in piece.find("PointData").findall("DataArray")}
        material = decode(piece.find("CellData").find("DataArray"))
        if n_cells == 0:
            errors.append(source + ": no tets")
        if len(material) != n_cells:
            errors.append(source + ": %d materials for %d tets" % (len(material), n_cells))
        if sorted(arrays) != sorted(point_arrays):
            errors.append(source + ": point arrays %s, the .pvtu says %s" % (sorted(arrays), sorted(point_arrays)))
        gid = arrays.get("global_id", ())
        if len(gid) != n_points:
            errors.append(source + ": %d global ids for %d points" % (len(gid), n_points))
        tets += n_cells
        ids.update(gid)
    vertices, gathered_tets = medit_counts(gathered)
    if tets != gathered_tets:
        errors.append("pieces have %d tets, the gathered mesh %d" % (tets, gathered_tets))
    if len(ids) != vertices:
        errors.append("pieces have %d distinct global ids, the gathered mesh %d vertices" % (len(ids), vertices))
    if "global_id" not in point_arrays:
        errors.append("no global_id array in the .pvtu")
    for e in errors:
        print(e)
    if not errors:
        print("%d pieces, %d tets, %d vertices: as gathered" % (len(pieces), tets, len(ids)))
    sys.exit(1 if errors else 0)


if __name__ == "__main__":
    main()
