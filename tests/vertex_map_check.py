#!/usr/bin/env python3
"""Checks a vertex map file (topotet simplify --vertex-map) against its input and output meshes,
without numpy or topotet's own readers: collapses only rename vertices, so with --optimize none
the output tets are exactly the input tets mapped through the map, less those whose images repeat
a vertex; every vertex a tet uses maps into the output, onto it; the others map to -1.
  usage: vertex_map_check.py MAP(.npy|.txt) IN.mesh OUT.mesh"""
import ast
import struct
import sys


def read_map(path):
    if path.endswith(".npy"):
        data = open(path, "rb").read()
        assert data[:8] == b"\x93NUMPY\x01\x00", "not a NumPy 1.0 file"
        size = struct.unpack("<H", data[8:10])[0]
        header = ast.literal_eval(data[10:10 + size].decode("latin1"))
        assert header["descr"] == "<i8" and not header["fortran_order"], header
        (n,) = header["shape"]
        body = data[10 + size:]
        assert len(body) == 8 * n, (len(body), n)
        return list(struct.unpack("<%dq" % n, body))
    return [int(line) for line in open(path) if line.strip() and not line.startswith("#")]


def read_medit(path):
    """Vertex count and tets (0-based, with material) of an ASCII MEDIT file."""
    tokens = open(path).read().split()
    vertices, tets, i = 0, [], 0
    while i < len(tokens):
        keyword = tokens[i]
        if keyword == "Vertices":
            vertices = int(tokens[i + 1])
            i += 2 + 4 * vertices
        elif keyword == "Tetrahedra":
            n = int(tokens[i + 1])
            for t in range(n):
                row = tokens[i + 2 + 5 * t: i + 7 + 5 * t]
                tets.append((tuple(int(x) - 1 for x in row[:4]), int(row[4])))
            i += 2 + 5 * n
        else:
            i += 1
    return vertices, tets


def main():
    vmap = read_map(sys.argv[1])
    n_in, tets_in = read_medit(sys.argv[2])
    n_out, tets_out = read_medit(sys.argv[3])
    assert len(vmap) == n_in, "map has %d entries for %d input vertices" % (len(vmap), n_in)
    used = set(v for t, _ in tets_in for v in t)
    for i, o in enumerate(vmap):
        if i in used:
            assert 0 <= o < n_out, "input vertex %d -> %d (output has %d)" % (i, o, n_out)
        else:
            assert o == -1, "unused input vertex %d -> %d" % (i, o)
    assert set(o for o in vmap if o >= 0) == set(range(n_out)), "not onto the output vertices"
    renamed = []
    for t, material in tets_in:
        image = tuple(sorted(vmap[v] for v in t))
        if len(set(image)) == 4:
            renamed.append((image, material))
    output = [(tuple(sorted(t)), material) for t, material in tets_out]
    assert sorted(renamed) == sorted(output), "the output tets are not the input tets renamed (%d vs %d)" % (
        len(renamed), len(output))
    print("vertex map ok: %d input vertices -> %d output vertices, %d tets" % (n_in, n_out, len(output)))


if __name__ == "__main__":
    main()
