#!/usr/bin/env bash
# bench/quality_vs_remesher.sh BUILD_DIR [CGAL_BIN_DIR] [options of bench/quality_vs_remesher.py]
# topotet beside CGAL's tetrahedral_isotropic_remeshing at the same vertex count (issue #26 item 4).
# CGAL_BIN_DIR defaults to build-cgal/bench/cgal (cmake -S . -B build-cgal -DTOPOTET_BENCH_CGAL=ON;
# bench/cgal/README.md). The work is done by bench/quality_vs_remesher.py (see its --help).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
if (($# < 1)); then
  echo "usage: $0 BUILD_DIR [CGAL_BIN_DIR] [--work DIR] [--only REGEX] [--ratios 0.1,0.02] ..." >&2
  exit 2
fi
build="$1"; shift
cgal="$here/../build-cgal/bench/cgal"
if (($# > 0)) && [[ $1 != -* ]]; then cgal="$1"; shift; fi
if [[ ! -x $cgal/cgal_remesh ]]; then
  echo "$0: no $cgal/cgal_remesh: configure a tree with -DTOPOTET_BENCH_CGAL=ON and build cgal_remesh cgal_segmentation" >&2
  exit 2
fi
exec /usr/bin/python3 "$here/quality_vs_remesher.py" "$build" "$cgal" "$@"
