#!/usr/bin/env bash
# libFuzzer under ASan+UBSan (clang 14), one target per input path we own:
#   fuzz_obj fuzz_ply fuzz_stl fuzz_off fuzz_gltf  each mesh format through hsr::loadMeshFile
#   fuzz_scene                                     bytes -> scene -> render at up to 64x64
#   fuzz_args                                      the CLI's scene and camera arguments
#   fuzz_bsp                                       BSP tree files through hsr::readBsp, rendered
#   fuzz_clip                                      two regions through Weiler-Atherton clipping
#   fuzz_camera                                    camera JSON, lists of views and pose text
#   fuzz_wad                                       Doom WADs: maps read, nodes built, written back, drawn
#   fuzz_obj_text                                  the web page's OBJ reader (hsr::parseObjText), drawn
# Usage: scripts/fuzz.sh [SECONDS_PER_TARGET (default 60)] [TARGET...]
#        scripts/fuzz.sh --merge [TARGET...]   minimise the working corpus into fuzz/corpus/
# Targets run HSR_FUZZ_JOBS at a time (default: one per core); each has its own core and its
# full SECONDS_PER_TARGET (a fuzzer is one process: two of them on two cores take the time one
# took alone).
# Each target starts from its committed corpus (fuzz/corpus/TARGET), the known-bug seeds of
# its format (fuzz/seeds/*.EXT; fuzz/seeds/args/ and scene/ for the two others) and, for mesh
# formats, Debian's assimp test models; what it finds goes to build-san/corpus/TARGET (the
# tree stays clean). Any crash, leak, timeout
# or out-of-memory fails the run; the input is kept in build-san/artifacts/TARGET/.
# A line per target is appended to build-san/fuzz-log.tsv: target, seconds, CPU seconds
# (the target and its import children), executions, coverage, corpus size, result.
set -euo pipefail
cd "$(dirname "$0")/.."
all=(fuzz_obj fuzz_ply fuzz_stl fuzz_off fuzz_gltf fuzz_scene fuzz_args fuzz_bsp fuzz_clip fuzz_camera fuzz_wad fuzz_obj_text)
merge=0
seconds=60
if [ "${1:-}" = "--merge" ]; then merge=1; shift; elif [[ "${1:-}" =~ ^[0-9]+$ ]]; then seconds=$1; shift; fi
targets=("$@")
[ ${#targets[@]} -eq 0 ] && targets=("${all[@]}")

scripts/install-deps.sh tests
echo "== libFuzzer build (clang, ASan+UBSan): the fuzz targets =="
# The sanitizer tree (scripts/test.sh builds its tests in it too): configured here only when new
if [ ! -f build-san/CMakeCache.txt ]; then
  generator=()
  command -v ninja >/dev/null && generator=(-G Ninja)
  CC=clang-14 CXX=clang++-14 cmake -S . -B build-san "${generator[@]}" -DHSR_BUILD_FUZZ=ON -DHSR_SANITIZE=ON \
    -DHSR_BUILD_TESTS=OFF -DHSR_BUILD_BENCH=OFF -DHSR_BUILD_PEERS=OFF \
    -DCMAKE_BUILD_TYPE=RelWithDebInfo >/dev/null
fi
cmake --build build-san -j"$(nproc)" --target "${all[@]}"

# libassimp leaks inside its ASCII STL reader (not ours): suppressed for LSan only.
# ASan's free-memory quarantine (256 MB by default) counts towards -rss_limit_mb=512; 64 MB
# keeps use-after-free detection without reading as an out-of-memory finding. ASan's
# allocator also keeps freed pages: fuzz_args reached 513 MB after 400,000 renders with 26 MB
# live (its input alone: 42 MB), so freed pages go back to the system every second.
export ASAN_OPTIONS=${ASAN_OPTIONS:-abort_on_error=0:quarantine_size_mb=64:allocator_release_to_os_interval_ms=1000}
export LSAN_OPTIONS=suppressions=$PWD/fuzz/lsan.supp
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
flags=(-max_len=65536 -rss_limit_mb=512 -timeout=10 -print_final_stats=1)
# The mesh targets' import child may use up to its memory limit (1 GiB for files this small;
# past it the file is refused) and reports any sanitizer or libFuzzer error of its own as a
# finding of this process. libFuzzer's per-allocation limit (by default the RSS limit) would
# end the child inside that budget, so for them it sits above it.
target_flags() {
  case $1 in fuzz_scene|fuzz_args|fuzz_bsp|fuzz_clip|fuzz_camera|fuzz_wad|fuzz_obj_text) ;; *) echo -malloc_limit_mb=2048 ;; esac
}

seed_dirs() {  # extra read-only seed directories for a target
  local t=$1 ext=${1#fuzz_} d=build-san/seeds/$1
  rm -rf "$d" && mkdir -p "$d"
  case $t in
  fuzz_scene|fuzz_args|fuzz_bsp|fuzz_clip|fuzz_camera|fuzz_wad|fuzz_obj_text)  # literal inputs: fuzz/seeds/args/, scene/, bsp/, clip/, camera/, wad/, obj_text/
    find "fuzz/seeds/$ext" -maxdepth 1 -type f -exec cp {} "$d/" \; 2>/dev/null || true ;;
  *)
    find fuzz/seeds -maxdepth 1 -type f -iname "*.$ext" -exec cp {} "$d/" \; 2>/dev/null || true
    [ "$ext" = gltf ] && find fuzz/seeds -maxdepth 1 -type f -iname "*.glb" -exec cp {} "$d/" \; || true
    # Debian's assimp test models of this format, those under the length limit
    find /usr/share/assimp/models -type f -iname "*.$ext" -size -64k -exec cp {} "$d/" \; 2>/dev/null || true
  esac
  echo "$d"
}

status=0
if [ $merge -eq 1 ]; then
  for t in "${targets[@]}"; do
    mkdir -p "build-san/corpus/$t" "build-san/artifacts/$t" "fuzz/corpus/$t"
    seed_dirs "$t" >/dev/null
    echo "== $t: minimising into fuzz/corpus/$t =="
    tmp=$(mktemp -d)
    "build-san/$t" -merge=1 "${flags[@]}" $(target_flags "$t") -artifact_prefix="build-san/artifacts/$t/" "$tmp" "fuzz/corpus/$t" "build-san/corpus/$t" \
      > "build-san/$t-merge.log" 2>&1
    rm -rf "fuzz/corpus/$t" && mv "$tmp" "fuzz/corpus/$t" && chmod 755 "fuzz/corpus/$t"
    echo "   $(ls "fuzz/corpus/$t" | wc -l) files, $(du -sh "fuzz/corpus/$t" | cut -f1)"
  done
  exit 0
fi

# One target for `seconds`: its line in build-san/fuzz-log.tsv, and its finding if any
run_target() {
  local t=$1 seeds log start rc cpu wall execs cov corp result
  mkdir -p "build-san/corpus/$t" "build-san/artifacts/$t" "fuzz/corpus/$t"
  seeds=$(seed_dirs "$t")
  log=build-san/$t.log
  start=$(date +%s)
  rc=0
  # CPU time of the fuzzer and its import children (bash's `time` counts reaped descendants)
  TIMEFORMAT='%U %S'
  { time { "build-san/$t" -max_total_time="$seconds" "${flags[@]}" $(target_flags "$t") \
             -artifact_prefix="build-san/artifacts/$t/" \
             "build-san/corpus/$t" "fuzz/corpus/$t" "$seeds" > "$log" 2>&1 || rc=$?; }; } \
    2> "build-san/$t.time"
  cpu=$(awk '{ printf "%.0f", $1 + $2 }' "build-san/$t.time")
  wall=$(( $(date +%s) - start ))
  # A finding while the seeds are read leaves no "cov:" line: the figures are then "?" (and
  # pipefail must not end the script before it reports the finding)
  execs=$(grep -o 'stat::number_of_executed_units: [0-9]*' "$log" | awk '{print $2}' | tail -1 || true)
  cov=$(grep -o 'cov: [0-9]*' "$log" | tail -1 | awk '{print $2}' || true)
  corp=$(ls "build-san/corpus/$t" | wc -l)
  result=ok
  [ "$rc" -ne 0 ] && result="FINDING (exit $rc)"
  echo "$result" > "build-san/$t.result"
  printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$t" "$wall" "${cpu:-?}" "${execs:-?}" "${cov:-?}" "$corp" "$result" \
    | tee -a build-san/fuzz-log.tsv
  if [ "$rc" -ne 0 ]; then
    grep -E "ERROR|SUMMARY|Test unit written|==[0-9]+==" "$log" | head -20 || true
    return 1
  fi
}

jobs_max=${HSR_FUZZ_JOBS:-$(nproc)}
echo "== ${#targets[@]} targets, ${seconds} s each, ${jobs_max} at a time =="
echo "target	seconds	cpu_s	executions	coverage	corpus	result"
for t in "${targets[@]}"; do
  rm -f "build-san/$t.result"
  while [ "$(jobs -rp | wc -l)" -ge "$jobs_max" ]; do wait -n || true; done
  run_target "$t" &
done
wait || true
# Each target's result from its own file: a job's exit status can be reaped before it is asked
for t in "${targets[@]}"; do
  [ "$(cat "build-san/$t.result" 2>/dev/null)" = ok ] || { echo "fuzz: $t: $(cat "build-san/$t.result" 2>/dev/null || echo 'no result')"; status=1; }
done
exit $status
