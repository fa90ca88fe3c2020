"""Simplifies a mesh held in numpy arrays: a cube of 8^3 cells, 6 tets each, a ball of material 2
inside. Usage: python3 simplify.py [DIR]  (also writes DIR/in.mesh and DIR/out.mesh)"""
import itertools
import sys

import numpy as np
import topotet

n = 8
grid = np.stack(np.meshgrid(*[np.arange(n + 1)] * 3, indexing="ij"), axis=-1).reshape(-1, 3)
points = grid.astype(np.float64)
vid = lambda c: c[..., 0] * (n + 1) ** 2 + c[..., 1] * (n + 1) + c[..., 2]
cubes = np.stack(np.meshgrid(*[np.arange(n)] * 3, indexing="ij"), axis=-1).reshape(-1, 1, 3)
tets = []
for order in itertools.permutations(range(3)):  # the 6 axis paths from a cube's low to high corner
    steps = np.cumsum(np.eye(3, dtype=int)[list(order)], axis=0)
    corners = vid(np.concatenate([cubes, cubes + steps], axis=1))
    if np.linalg.det(steps) < 0:  # odd axis order: negatively oriented, swap two corners
        corners = corners[:, [0, 1, 3, 2]]
    tets.append(corners)
tets = np.concatenate(tets)
centres = points[tets].mean(axis=1) - n / 2
materials = np.where((centres**2).sum(axis=1) < 6.0, 2, 1)
temperature = points[:, 0] + np.sin(points[:, 1])

out = topotet.simplify(points, tets, materials=materials, fields={"T": temperature}, ratio=0.2, threads=2)
vmap = out["vertex_map"]  # for every input point, the output point it merged into
assert vmap.shape == (len(points),) and vmap.min() >= 0 and vmap.max() < len(out["points"])
farthest = np.linalg.norm(out["points"][vmap] - points, axis=1).max()
r = out["report"]
print(f"{r['status']}: {r['vertices_before']} -> {len(out['points'])} vertices, "
      f"{r['tets_before']} -> {len(out['tets'])} tets, farthest merge {farthest:.2f} cells")
if len(sys.argv) > 1:
    topotet.write(f"{sys.argv[1]}/in.mesh", {"points": points, "tets": tets, "materials": materials})
    topotet.write(f"{sys.argv[1]}/out.mesh", out)
