#!/usr/bin/env bash
# Installs a built tree into a temporary prefix, then builds the examples against it as an
# out-of-tree consumer, once with find_package(topotet CONFIG) and once with pkg-config, runs them,
# and checks the C and Fortran outputs with `topotet check`; runs the Python example on the
# installed module; checks that the README's snippets are excerpts of the examples built here.
# Usage: install_test.sh BUILD_DIR SOURCE_DIR [PYTHON]
set -euo pipefail
build=$(cd "$1" && pwd)
src=$(cd "$2" && pwd)
python=${3:-}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
prefix=$work/prefix

cmake --install "$build" --prefix "$prefix" >/dev/null
pc=$(find "$prefix" -name topotet.pc)
test -n "$pc" || { echo "no topotet.pc installed"; exit 1; }
test -f "$(dirname "$pc")/../cmake/topotet/topotetConfigVersion.cmake" || { echo "no topotetConfigVersion.cmake"; exit 1; }
test -f "$prefix/include/topotet/version.h" || { echo "no topotet/version.h"; exit 1; }
cli=$prefix/bin/topotet
echo "--- installed: $(cd "$prefix" && find . -type f | sort | tr '\n' ' ')"

echo "--- find_package(topotet CONFIG)"
generator=()
if command -v ninja >/dev/null; then generator=(-G Ninja); fi
# glm is internal: the package must configure with find_package(glm) made to fail (it is never
# even called, hence --no-warn-unused-cli).
cmake -S "$src/examples" -B "$work/consumer" "${generator[@]}" -DCMAKE_BUILD_TYPE=Release --no-warn-unused-cli \
  -DCMAKE_DISABLE_FIND_PACKAGE_glm=ON -DCMAKE_PREFIX_PATH="$prefix" >"$work/configure.log" || { cat "$work/configure.log"; exit 1; }
cmake --build "$work/consumer" -j2 >"$work/build.log" || { cat "$work/build.log"; exit 1; }
"$work/consumer/simplify_cpp"
mkdir -p "$work/c" "$work/f90"
"$work/consumer/simplify_c" "$work/c"
"$cli" check "$work/c/in.mesh" "$work/c/out.mesh" --fast >"$work/check.log" || { cat "$work/check.log"; exit 1; }
echo "C output: topology check passed"
if [[ -x $work/consumer/simplify_f90 ]]; then
  "$work/consumer/simplify_f90" "$work/f90"
  "$cli" check "$work/f90/in.mesh" "$work/f90/out.mesh" --fast >"$work/check.log" || { cat "$work/check.log"; exit 1; }
  echo "Fortran output: topology check passed"
elif command -v gfortran >/dev/null; then
  echo "gfortran is installed but the package has no topotet::fortran"; exit 1
fi
if [[ -x $work/consumer/distributed_simplify ]]; then
  OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_mpi_yield_when_idle=1 \
    mpirun -np 2 --oversubscribe --bind-to none "$work/consumer/distributed_simplify"
  echo "MPI example (topotet::mpi from the package): ran on 2 ranks"
elif [[ -x $prefix/bin/topotet-mpi ]]; then
  echo "topotet-mpi is installed but the package has no topotet::mpi"; exit 1
fi

if [[ -x $work/consumer/convert_vtk ]]; then
  mkdir -p "$work/vtk"
  "$cli" generate cube-sphere --tets 3000 -o "$work/vtk/in.vtu" -q
  "$work/consumer/convert_vtk" "$work/vtk/in.vtu" "$work/vtk/out.exo"
  "$cli" check "$work/vtk/in.vtu" "$work/vtk/out.exo" --fast >"$work/check.log" || { cat "$work/check.log"; exit 1; }
  echo "VTK component (topotet::io_vtk from the package): .vtu -> .exo, topology check passed"
elif compgen -G "$prefix/lib*/libtopotet_io_vtk*" >/dev/null; then
  echo "libtopotet_io_vtk is installed but the package has no topotet::io_vtk"; exit 1
fi

echo "--- pkg-config"
export PKG_CONFIG_PATH=$(dirname "$pc")

echo "--- no glm for consumers"
if grep -rl glm "$prefix/include" "$pc" "$(dirname "$pc")/../cmake/topotet"; then
  echo "the installed headers or package files above name glm"; exit 1
fi
# What the C++ example really includes (the compiler's own list): no glm header among them.
if c++ -std=c++20 -M "$src/examples/cpp/simplify.cpp" $(pkg-config --cflags topotet) | grep /glm/; then
  echo "the C++ example includes glm through topotet's headers"; exit 1
fi
echo "no installed header, CMake file or topotet.pc needs glm"
# (-rpath: a shared topotet in a prefix the loader does not search.)
rpath=-Wl,-rpath,$(pkg-config --variable=libdir topotet)
c++ -std=c++20 -O1 "$src/examples/cpp/simplify.cpp" -o "$work/pc_cpp" $(pkg-config --cflags --libs --static topotet) "$rpath"
"$work/pc_cpp"
cc -O1 "$src/examples/c/simplify.c" -o "$work/pc_c" $(pkg-config --cflags --libs --static topotet) -lm "$rpath"
"$work/pc_c"

if [[ -n $python ]]; then
  echo "--- Python package"
  package=$(find "$prefix" -name '__init__.py' -path '*python*/topotet/*' | head -1)
  test -n "$package" || { echo "no Python package installed"; exit 1; }
  compgen -G "$(dirname "$package")/_core*.so" >/dev/null || { echo "the package has no extension _core"; exit 1; }
  mkdir -p "$work/py"
  PYTHONPATH=$(dirname "$(dirname "$package")") "$python" "$src/examples/python/simplify.py" "$work/py"
  "$cli" check "$work/py/in.mesh" "$work/py/out.mesh" --fast >"$work/check.log" || { cat "$work/check.log"; exit 1; }
  echo "Python output: topology check passed"
fi

echo "--- README: every snippet marked <!-- from examples/FILE --> is a verbatim excerpt of FILE"
"${python:-python3}" "$src/tests/readme_snippets.py" "$src/README.md" "$src/examples"
echo "install_test: pass"
