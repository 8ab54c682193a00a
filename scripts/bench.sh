#!/usr/bin/env bash
# Builds Release and runs every registered algorithm vs llvmpipe (bench/bench_algorithms.cpp)
# and hsr's rays vs Embree (bench/bench_rays.cpp) with HSR_BENCH_THREADS=1 and 2, and hsr's
# line drawings vs Open CASCADE's hidden-line removal (bench/bench_lines.cpp; OCCT runs on one
# thread, so the race runs once, at 1 thread, with hsr alone again at the others), and the Doom
# node builder vs ZDBSP (bench/bench_doom.cpp, once: both build on one thread), and the web page's
# WebAssembly module against the native build (bench/bench_web.mjs, one thread)
# (plus any thread counts given as arguments, e.g. `scripts/bench.sh 4 8`), then prints the
# ratio tables of all runs together. BUILD_DIR (default build) and JOBS (default 2)
# may be set; extra Google Benchmark flags go in BENCH_ARGS.
set -euo pipefail
cd "$(dirname "$0")/.."
build_dir="${BUILD_DIR:-build}"
jobs="${JOBS:-2}"
cmake -S . -B "$build_dir" -DCMAKE_BUILD_TYPE=Release -DHSR_BUILD_BENCH=ON >/dev/null
cmake --build "$build_dir" --target hsr_bench hsr_bench_rays hsr_bench_lines hsr_bench_doom -j "$jobs"
out="$(mktemp -d)"
trap 'rm -rf "$out"' EXIT
for t in 1 2 "$@"; do
  echo "=== HSR_BENCH_THREADS=$t ==="
  # shellcheck disable=SC2086
  HSR_BENCH_THREADS="$t" "$build_dir/hsr_bench" ${BENCH_ARGS:-} | tee "$out/threads-$t.txt"
  # shellcheck disable=SC2086
  HSR_BENCH_THREADS="$t" "$build_dir/hsr_bench_rays" ${BENCH_ARGS:-} | tee "$out/rays-$t.txt"
  filter=""
  [ "$t" != 1 ] && filter="--benchmark_filter=BM_hsr"
  # shellcheck disable=SC2086
  HSR_BENCH_THREADS="$t" "$build_dir/hsr_bench_lines" $filter ${BENCH_ARGS:-} | tee "$out/lines-$t.txt"
done
echo
echo "=== speed ratios (llvmpipe time / algorithm time; > 1 means hsr is faster) ==="
for t in 1 2 "$@"; do
  grep -E "^threads=" "$out/threads-$t.txt" || true
  echo
done
echo "=== object order (time as a multiple of the z-buffer's, tests and splits, growth) ==="
for t in 1 2 "$@"; do
  sed -n '/^object order vs zbuffer/,/^(x zbuffer/p' "$out/threads-$t.txt"
  echo
done
echo "=== rays vs Embree (Embree time / hsr time) and the builds ==="
for t in 1 2 "$@"; do
  sed -n '/^rays vs Embree/,$p' "$out/rays-$t.txt"
  echo
done
echo "=== line drawings vs Open CASCADE (OCCT time / hsr time) ==="
for t in 1 2 "$@"; do
  sed -n '/^full drawings/,$p' "$out/lines-$t.txt"
  echo
done
echo "=== Doom node builder vs ZDBSP (whole WAD, whole process; ZDBSP is single-threaded, so is hsr's build) ==="
"$build_dir/hsr_bench_doom"
echo "=== the web page's WebAssembly vs the native build, one thread (warm frames) ==="
cmake --preset wasm >/dev/null && cmake --build --preset wasm --target hsr_web >/dev/null
node bench/bench_web.mjs build-wasm/web "$build_dir/hsr"
