#!/usr/bin/env bash
# Fuzzing smoke run: the mesh readers and writers (tests/fuzz/fuzz_readers.cpp), then the simplifier
# on fuzzed valid meshes refereed by the topology checker (tests/fuzz/fuzz_simplify.cpp), under
# libFuzzer with ASan and UBSan for a short time each, the readers seeded with the small committed meshes. Any crash, sanitizer
# report or leak fails the job; the corpus and any crash input are left in build-fuzz/.
# Usage: bash scripts/fuzz_smoke.sh [SECONDS]   (default 60; needs clang and libclang-rt-14-dev, which setup.sh --tests installs)
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
seconds=${1:-60}
cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g1 -DNDEBUG" -DCMAKE_CXX_COMPILER=clang++ \
  -DCMAKE_C_COMPILER=clang -DTOPOTET_FUZZ=ON -DTOPOTET_SANITIZE=address,undefined -DTOPOTET_BUILD_BENCH=OFF
cmake --build build-fuzz -j "$(nproc)" --target fuzz_readers fuzz_simplify
corpus=build-fuzz/fuzz_corpus
mkdir -p "$corpus" build-fuzz/fuzz_artifacts
cp tests/data/*.msh "$corpus/"
# Tiny TetGen and mixed MEDIT seeds (the target reads every input as each format).
printf '5 3 0 1\n1 0 0 0 1\n2 1 0 0 1\n3 0 1 0 0\n4 0 0 1 1\n5 1 1 1 0\n' >"$corpus/seed.node"
printf '2 4 1\n1 1 2 3 4 7\n2 2 3 4 5 8\n' >"$corpus/seed.ele"
printf 'Dimension 3\nVertices\n5\n0 0 0 0\n1 0 0 0\n0 1 0 0\n0 0 1 0\n1 1 1 0\nTetrahedra\n1\n1 2 3 4 1\nPyramids\n1\n1 2 3 4 5 2\nCorners\n2\n1\n9\nEnd\n' \
  >"$corpus/seed_mixed.mesh"
# A binary MEDIT seed (.meshb, version 3: two tets).
python3 - "$corpus/seed.meshb" <<'EOF'
import struct, sys
out = bytearray(struct.pack("<ii", 1, 3))
def keyword(code, body):
    out.extend(struct.pack("<iq", code, len(out) + 12 + len(body)) + body)
keyword(3, struct.pack("<i", 3))
vertices = [(0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1), (1, 1, 1)]
keyword(4, struct.pack("<i", 5) + b"".join(struct.pack("<dddi", *p, 0) for p in vertices))
keyword(8, struct.pack("<i", 2) + struct.pack("<5i", 1, 2, 3, 4, 1) + struct.pack("<5i", 2, 3, 4, 5, 2))
keyword(6, struct.pack("<i", 1) + struct.pack("<4i", 2, 3, 4, 7))
out.extend(struct.pack("<iq", 54, 0))
open(sys.argv[1], "wb").write(out)
EOF
# A hierarchy seed (.tth, docs/formats.md: two tets, one collapse that removes one of them).
python3 - "$corpus/seed.tth" <<'EOF'
import struct, sys
q = lambda n: struct.pack("<Q", n)
out = b"TOPOTETH" + struct.pack("<II", 1, 0)
out += q(5) + struct.pack("<15d", 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0, 1, 1, 1, 1) + q(0)
out += q(2) + struct.pack("<8I", 0, 1, 2, 3, 1, 2, 3, 4) + struct.pack("<2i", 1, 2)
out += q(0) + q(0) + q(0) + q(0) + q(0) + q(0) + q(0)  # triangles .. fields, group names
out += q(1) + struct.pack("<I", 0) + struct.pack("<II", 3, 4) + struct.pack("<9d", 0, 0, 1, 0, 0, 1, 1, 1, 1)
out += struct.pack("<d", 0.5) + struct.pack("<f", float("nan")) + struct.pack("<II", 0, 0) + b"TTH_END!"
open(sys.argv[1], "wb").write(out)
EOF
# A vertex map seed (.npy: read as every format, and as a map).
python3 - "$corpus/seed_map.npy" <<'EOF'
import struct, sys
h = "{'descr': '<i8', 'fortran_order': False, 'shape': (3,), }"
h += " " * (127 - 10 - len(h)) + "\n"
open(sys.argv[1], "wb").write(b"\x93NUMPY\x01\x00" + struct.pack("<H", len(h)) + h.encode() + struct.pack("<3q", 0, 0, -1))
EOF
build-fuzz/tests/fuzz_readers -max_total_time="$seconds" -rss_limit_mb=2048 -max_len=20000 \
  -dict=tests/fuzz/readers.dict -artifact_prefix=build-fuzz/fuzz_artifacts/ "$corpus"
echo "fuzz smoke (readers): no crash in ${seconds} s; corpus: $(ls "$corpus" | wc -l) files"
mkdir -p build-fuzz/fuzz_simplify_corpus
build-fuzz/tests/fuzz_simplify -max_total_time="$seconds" -rss_limit_mb=2048 -max_len=64 -len_control=0 \
  -artifact_prefix=build-fuzz/fuzz_artifacts/simplify- build-fuzz/fuzz_simplify_corpus
echo "fuzz smoke (simplify): no crash, no topology change in ${seconds} s"
