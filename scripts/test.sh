#!/usr/bin/env bash
# Install, build and pass every test; this is what CI runs (.ci/run). The legs, in order:
#   1. Release (GCC, link-time optimisation, SIMD span path): the library, the CLI, the Python
#      module (linked from the library's plain code: HSR_PYTHON_LTO=OFF), both test programs
#      (hsr's own tests, and the peer-agreement tests against Mesa, Embree, Open CASCADE, CGAL
#      and ZDBSP) and the benchmarks' sources (compiled, not linked: HSR_BENCH_LINK=OFF); then
#      every test under CTest, two at a time.
#   2. The web page (scripts/test-web.sh): its WebAssembly build against the native one, under
#      node and in headless Chromium.
#   3. ASan+UBSan (clang 14, one tree, build-san, for this leg and the next: hsr's code with the
#      sanitizers and libFuzzer's coverage, the tests uninstrumented around it): hsr's own tests
#      again. The peers are other people's code and are checked once, in leg 1.
#   4. libFuzzer (the same tree): every target for HSR_FUZZ_SECONDS (default 30) from the
#      committed corpus, one per core at a time.
# Every leg's time goes to build/ci-times.tsv and is printed at the end (docs/testing.md keeps
# the table). HSR_TEST_INTENSITY: 1 (default, CI) or 3 for long local runs.
# Usage: scripts/test.sh            every leg (what CI runs)
#        scripts/test.sh --quick    leg 1 alone, for a contributor between changes (a few minutes
#                                   once built); not what CI runs
set -euo pipefail
cd "$(dirname "$0")/.."
export HSR_TEST_INTENSITY=${HSR_TEST_INTENSITY:-1}
fuzz_seconds=${HSR_FUZZ_SECONDS:-30}
quick=0
case "${1:-}" in
  --quick) quick=1 ;;
  "") ;;
  *) echo "usage: scripts/test.sh [--quick]" >&2; exit 2 ;;
esac
times=$(mktemp)
trap 'rm -f "$times"' EXIT
t0=$(date +%s)
stage() {  # stage NAME COMMAND...: runs it, records its seconds
  local name=$1 start
  shift
  echo "== $name =="
  start=$(date +%s)
  "$@"
  printf '%s\t%s\n' "$name" "$(( $(date +%s) - start ))" | tee -a "$times"
}
ctest_run() {  # ctest_run DIR [extra ctest args]
  local dir=$1
  shift
  ctest --test-dir "$dir" --output-on-failure --no-tests=error -j"$(nproc)" "$@"
}

stage "install the Debian packages" scripts/install-deps.sh
# Options stated, not inherited: a build/ left by scripts/demo.sh has the tests, the benchmarks
# and the Python module switched off
# The Release build prints no compiler warning: one printed fails the leg
release_build() {
  local log
  log=$(mktemp)
  scripts/build.sh build -DHSR_BUILD_TESTS=ON -DHSR_BUILD_BENCH=ON -DHSR_BENCH_LINK=OFF \
    -DHSR_BUILD_PYTHON=ON -DHSR_PYTHON_LTO=OFF -DHSR_BUILD_PEERS=ON 2>&1 | tee "$log"
  local warnings
  warnings=$(grep -c "warning:" "$log" || true)
  rm -f "$log"
  if [ "$warnings" -gt 0 ]; then
    echo "test: the Release build printed $warnings compiler warnings (above); it must print none" >&2
    return 1
  fi
}
stage "Release build" release_build
stage "Release tests" ctest_run build
if [ $quick -eq 1 ]; then
  echo "== quick: the Release suite passed (CI also runs the web page, ASan+UBSan and the fuzzers) =="
  exit 0
fi
stage "web page: build and tests" scripts/test-web.sh build/hsr
# One clang tree for legs 3 and 4: hsr's code compiled once, with the sanitizers and libFuzzer's
# coverage, for the tests and the fuzz targets alike
CC=clang-14 CXX=clang++-14 stage "ASan+UBSan build (clang: the tests and the fuzz targets)" \
  scripts/build.sh build-san -DHSR_BUILD_TESTS=ON -DHSR_SANITIZE=ON -DHSR_BUILD_FUZZ=ON \
  -DHSR_BUILD_BENCH=OFF -DCMAKE_BUILD_TYPE=RelWithDebInfo
# Leak checking stays off for the tests (the fuzz targets keep it, scripts/fuzz.sh).
ASAN_OPTIONS=detect_leaks=0:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  stage "ASan+UBSan tests" ctest_run build-san
stage "libFuzzer: ${fuzz_seconds} s per target" scripts/fuzz.sh "$fuzz_seconds"

mkdir -p build
{ cat "$times"; printf 'total\t%s\n' "$(( $(date +%s) - t0 ))"; } > build/ci-times.tsv
echo "== time per leg (seconds) =="
column -t -s $'\t' build/ci-times.tsv
