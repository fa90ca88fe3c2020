#!/usr/bin/env bash
# Line and region coverage of the fuzz corpora: which code of the readers, writers, builder and
# simplifier the fuzzers have reached. Builds the two fuzz targets with clang's source-based
# coverage (no sanitizers: they do not change what runs), replays each corpus once (-runs=0) and
# prints llvm-cov's per-file table for the code the targets exercise.
# Usage: bash scripts/fuzz_coverage.sh [READERS_CORPUS] [SIMPLIFY_CORPUS]
#   (defaults: the corpora scripts/fuzz_smoke.sh grows in build-fuzz/); the report is also written
#   to build-cov/coverage.txt, and an HTML view to build-cov/html/.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
readers_corpus=${1:-build-fuzz/fuzz_corpus}
simplify_corpus=${2:-build-fuzz/fuzz_simplify_corpus}
for dir in "$readers_corpus" "$simplify_corpus"; do
  [[ -d $dir ]] || { echo "fuzz_coverage: no corpus $dir (run scripts/fuzz_smoke.sh first)" >&2; exit 2; }
done
llvm_version=$(clang++ --version | sed -n 's/.*clang version \([0-9]*\).*/\1/p')
profdata=$(command -v "llvm-profdata-$llvm_version" || command -v llvm-profdata)
cov=$(command -v "llvm-cov-$llvm_version" || command -v llvm-cov)
flags="-fprofile-instr-generate -fcoverage-mapping"
cmake -S . -B build-cov -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DCMAKE_CXX_COMPILER=clang++ \
  -DCMAKE_C_COMPILER=clang -DTOPOTET_FUZZ=ON -DTOPOTET_BUILD_BENCH=OFF -DTOPOTET_BUILD_CLI=OFF \
  -DTOPOTET_BUILD_C_API=OFF -DTOPOTET_BUILD_FORTRAN=OFF -DTOPOTET_BUILD_PYTHON=OFF \
  -DCMAKE_CXX_FLAGS="$flags" -DCMAKE_C_FLAGS="$flags" -DCMAKE_EXE_LINKER_FLAGS="$flags" >/dev/null
cmake --build build-cov -j "$(nproc)" --target fuzz_readers fuzz_simplify
rm -f build-cov/*.profraw
LLVM_PROFILE_FILE=build-cov/readers-%p.profraw build-cov/tests/fuzz_readers -runs=0 -rss_limit_mb=2048 \
  "$readers_corpus" 2>build-cov/readers.log
LLVM_PROFILE_FILE=build-cov/simplify-%p.profraw build-cov/tests/fuzz_simplify -runs=0 -rss_limit_mb=2048 \
  "$simplify_corpus" 2>build-cov/simplify.log
"$profdata" merge -sparse build-cov/*.profraw -o build-cov/fuzz.profdata
objects=(build-cov/tests/fuzz_readers -object build-cov/tests/fuzz_simplify)
# The project's own code only (no system headers, no test harness).
ignore='(/usr/|tests/)'
"$cov" report "${objects[@]}" -instr-profile=build-cov/fuzz.profdata -ignore-filename-regex="$ignore" |
  tee build-cov/coverage.txt
"$cov" show "${objects[@]}" -instr-profile=build-cov/fuzz.profdata -ignore-filename-regex="$ignore" \
  -format=html -output-dir=build-cov/html >/dev/null
echo "fuzz_coverage: corpora $(ls "$readers_corpus" | wc -l) + $(ls "$simplify_corpus" | wc -l) inputs;" \
  "table in build-cov/coverage.txt, HTML in build-cov/html/index.html"
