#!/usr/bin/env bash
# Installs the Debian 12 packages topotet needs (apt is skipped when all are installed) and builds
# into build/ (Release, Ninja).
#   bash scripts/setup.sh            the library and the topotet CLI only: the few packages they
#                                    need, and the targets `topotet demo` runs (README command 1)
#   bash scripts/setup.sh --tests    everything: the test tools (gmsh, tetgen, clang for the
#                                    fuzzers, GoogleTest), MPI and METIS, Fortran, Python, VTK (the
#                                    VTK formats, io/vtk/); every target, tests and benchmarks
#                                    included (README command 2, CI)
#   bash scripts/setup.sh --paraview the ParaView plugin (paraview/, docs/paraview.md): ParaView 5.11's
#                                    packages, and a tree of its own, build-paraview/, on ParaView's
#                                    VTK: the plugin, the CLI and the plugin's tests. Not with
#                                    --tests: Debian's python3-paraview (which ParaView's CMake
#                                    package needs) conflicts with libvtk9-dev, so apt removes
#                                    libvtk9-dev here, and --tests would put it back (removing
#                                    python3-paraview). CI (.ci/run) runs it last, after every job that uses libvtk9-dev.
# Other arguments go to the CMake configure step, e.g.
#   bash scripts/setup.sh --tests -DTOPOTET_SANITIZE=address,undefined
# Runs as root, or as a user with sudo, with no terminal (CI). Running the first form after the
# second keeps the full configuration's targets but builds only the CLI.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

all=0
paraview=0
cmake_args=()
for a in "$@"; do
  if [[ $a == --tests ]]; then all=1; elif [[ $a == --paraview ]]; then paraview=1; else cmake_args+=("$a"); fi
done
if ((all && paraview)); then
  echo "setup: --tests and --paraview cannot be combined: Debian's libvtk9-dev and python3-paraview conflict" >&2
  exit 2
fi

# What the library and the CLI need to build and run.
packages=(
  git cmake g++ ninja-build
  libtbb-dev libembree-dev libglm-dev zlib1g-dev
  libcli11-dev nlohmann-json3-dev
)
if ((all)); then
  packages+=(
    libgtest-dev libbenchmark-dev
    gmsh tetgen
    clang libclang-rt-14-dev
    gfortran pkg-config pybind11-dev python3-dev python3-numpy python3-pybind11
    python3-venv python3-setuptools python3-wheel python3-meshio python3-vtk9
    openmpi-bin libopenmpi-dev libmetis-dev
    libvtk9-dev
  )
fi

if ((paraview)); then
  # ParaView's own VTK serves the VTK formats in build-paraview/; GoogleTest for the filter's test.
  packages+=(paraview paraview-dev python3-paraview libgtest-dev)
fi

missing=()
for p in "${packages[@]}"; do
  if [[ $(dpkg-query -W -f='${Status}' "$p" 2>/dev/null) != "install ok installed" ]]; then missing+=("$p"); fi
done

if ((paraview)) && [[ $(dpkg-query -W -f='${Status}' libvtk9-dev 2>/dev/null) == "install ok installed" ]]; then
  echo "setup: python3-paraview conflicts with libvtk9-dev: apt removes libvtk9-dev (and python3-vtk9);" \
       "a build/ tree reconfigured without it loses the VTK formats until setup.sh --tests puts it back"
fi
if ((${#missing[@]} > 0)); then
  echo "setup: installing ${missing[*]}"
  sudo=()
  if [[ $(id -u) != 0 ]]; then sudo=(sudo); fi
  export DEBIAN_FRONTEND=noninteractive
  "${sudo[@]}" apt-get update -q
  "${sudo[@]}" apt-get install -y -q --no-install-recommends "${missing[@]}"
else
  echo "setup: all ${#packages[@]} packages already installed"
fi

if ((paraview)); then
  # A tree of its own (paraview/README.md says why): the plugin, the CLI (its pvbatch test runs
  # `topotet check`) and the tests, on ParaView's VTK.
  generator=()
  if [[ ! -f build-paraview/CMakeCache.txt ]]; then generator=(-G Ninja); fi
  cmake -S . -B build-paraview "${generator[@]}" -DCMAKE_BUILD_TYPE=Release -DTOPOTET_BUILD_PARAVIEW=ON \
    -DTOPOTET_BUILD_TESTS=ON -DTOPOTET_BUILD_BENCH=OFF -DTOPOTET_BUILD_PYTHON=OFF -DTOPOTET_BUILD_FORTRAN=OFF \
    -DTOPOTET_MPI=OFF "${cmake_args[@]}"
  cmake --build build-paraview -j "$(nproc)" --target TopotetSimplify topotet paraview_filter
  echo "setup: plugin in build-paraview/lib/topotet/paraview/; test: ctest --test-dir build-paraview -R 'ParaView|paraview'"
  exit 0
fi

# An existing build tree keeps its generator; a new one uses Ninja.
generator=()
if [[ ! -f build/CMakeCache.txt ]]; then generator=(-G Ninja); fi
if ((all)); then
  # Explicit ONs: a tree first configured by the short form has these cached OFF.
  cmake -S . -B build "${generator[@]}" -DCMAKE_BUILD_TYPE=Release \
    -DTOPOTET_BUILD_TESTS=ON -DTOPOTET_BUILD_BENCH=ON -DTOPOTET_BUILD_PYTHON=ON -DTOPOTET_BUILD_FORTRAN=ON \
    -DTOPOTET_MPI=ON -DTOPOTET_VTK=ON "${cmake_args[@]}"
  cmake --build build -j "$(nproc)"
else
  # A tree the full form configured keeps its options; a new one gets only what the CLI needs.
  options=()
  if [[ ! -f build/CMakeCache.txt ]]; then
    options=(-DTOPOTET_BUILD_TESTS=OFF -DTOPOTET_BUILD_BENCH=OFF -DTOPOTET_BUILD_PYTHON=OFF
             -DTOPOTET_BUILD_FORTRAN=OFF -DTOPOTET_MPI=OFF -DTOPOTET_VTK=OFF)
  fi
  cmake -S . -B build "${generator[@]}" -DCMAKE_BUILD_TYPE=Release "${options[@]}" "${cmake_args[@]}"
  cmake --build build -j "$(nproc)" --target topotet
fi
