#!/usr/bin/env bash
# `pip install .` (pyproject.toml + setup.py) into a fresh virtual environment, offline, as a user
# would do it; the module is then imported from the venv, outside the source tree, and simplifies
# a mesh. To keep the test short, setup.py reuses this build tree's module
# (TOPOTET_CMAKE_BUILD_DIR) instead of building the library a second time.
#   usage: bash tests/pip_install_test.sh PYTHON SOURCE_DIR BUILD_DIR
set -euo pipefail
python=${1:?usage: pip_install_test.sh PYTHON SOURCE_DIR BUILD_DIR}
src=$(realpath "${2:?}")
build=$(realpath "${3:?}")
work=$(mktemp -d "${TMPDIR:-/tmp}/topotet_pip_test.XXXXXX")
trap 'rm -rf "$work"' EXIT

# A copy of the sources without build trees, so that the checkout gets no build/ or egg-info.
mkdir "$work/src"
tar -C "$src" --exclude='./build*' --exclude='./.git' --exclude='./out' -cf - . | tar -C "$work/src" -xf -

"$python" -m venv --system-site-packages "$work/venv"
TOPOTET_CMAKE_BUILD_DIR="$build" "$work/venv/bin/python" -m pip install --no-build-isolation --no-index --no-deps \
  --quiet "$work/src"

version=$(sed -n 's/^project(topotet VERSION \([0-9.]*\).*/\1/p' "$src/CMakeLists.txt")
"$work/venv/bin/python" -m pip show topotet | grep -x "Version: $version" >/dev/null || {
  echo "FAIL: pip show topotet does not say Version: $version"
  exit 1
}

cd "$work"
"$work/venv/bin/python" - <<'PY'
import os, sys
import numpy as np
import topotet

where = os.path.realpath(topotet.__file__)
assert where.startswith(os.path.realpath(sys.prefix) + os.sep), f"imported from {where}, not the venv {sys.prefix}"
# A 4x4x4 grid of cubes, 6 tets each, two materials.
n = 4
g = np.stack(np.meshgrid(*[np.arange(n + 1.0)] * 3, indexing="ij"), axis=-1).reshape(-1, 3)
vid = lambda i, j, k: (i * (n + 1) + j) * (n + 1) + k
tets = []
for i in range(n):
    for j in range(n):
        for k in range(n):
            c = [vid(i + a, j + b, k + d) for a in (0, 1) for b in (0, 1) for d in (0, 1)]
            for t in ((0, 1, 3, 7), (0, 3, 2, 7), (0, 2, 6, 7), (0, 6, 4, 7), (0, 4, 5, 7), (0, 5, 1, 7)):
                tets.append([c[x] for x in t])
tets = np.array(tets)
p = g[tets]
vol = np.einsum("ij,ij->i", np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), p[:, 3] - p[:, 0])
tets[vol < 0] = tets[vol < 0][:, [0, 2, 1, 3]]
materials = np.where(p[:, :, 0].mean(axis=1) < 2, 1, 2).astype(np.int32)
out = topotet.simplify(g, tets, materials=materials, ratio=0.3, threads=1)
rep = out["report"]
assert rep["status"] in ("ok", "stopped_early"), rep["status"]
assert len(out["points"]) < len(g) and rep["tolerance"] > 0, rep
assert sorted(np.unique(out["materials"])) == [1, 2]
# The package, not only its extension: the adapters and python -m topotet come with it.
import subprocess
assert callable(topotet.from_meshio) and callable(topotet.to_meshio) and callable(topotet.default_options)
assert os.path.realpath(topotet._core.__file__).startswith(os.path.dirname(where))
run = subprocess.run([sys.executable, "-m", "topotet", "--help"], capture_output=True, text=True)
assert run.returncode == 0 and "simplify" in run.stdout, run
print(f"pip-installed topotet {topotet.__version__} from {where}: {len(g)} -> {len(out['points'])} vertices")
PY
