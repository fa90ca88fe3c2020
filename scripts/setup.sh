#!/usr/bin/env bash
# Installs the Debian 12 packages topotet needs (apt is skipped when all are installed) and builds
# everything (Release, Ninja) into build/. Extra arguments go to the CMake configure step, e.g.
#   bash scripts/setup.sh -DTOPOTET_SANITIZE=address,undefined
# Runs as root, or as a user with sudo, with no terminal (CI).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

packages=(
  git cmake g++ ninja-build
  libtbb-dev libembree-dev libglm-dev zlib1g-dev
  libgtest-dev libbenchmark-dev libcli11-dev nlohmann-json3-dev
  gmsh tetgen
  clang libclang-rt-14-dev
  gfortran pkg-config pybind11-dev python3-dev python3-numpy python3-pybind11
  openmpi-bin libopenmpi-dev libmetis-dev
)

missing=()
for p in "${packages[@]}"; do
  if [[ $(dpkg-query -W -f='${Status}' "$p" 2>/dev/null) != "install ok installed" ]]; then missing+=("$p"); fi
done

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

# An existing build tree keeps its generator; a new one uses Ninja.
generator=()
if [[ ! -f build/CMakeCache.txt ]]; then generator=(-G Ninja); fi
cmake -S . -B build "${generator[@]}" -DCMAKE_BUILD_TYPE=Release "$@"
cmake --build build -j "$(nproc)"
