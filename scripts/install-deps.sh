#!/usr/bin/env bash
# Installs the Debian packages hsr needs, by purpose. Idempotent: only what is missing is
# installed, and the list is printed first.
# Usage: scripts/install-deps.sh [PURPOSE...]   (default: all)
#   cli     the library and the hsr command (what scripts/demo.sh needs): 14 packages, a
#           compiler, CMake, Ninja, pkg-config and ten libraries
#   python  the Python module (python/)
#   tests   the test suites, their oracles and peers (Mesa, Embree, CGAL, Open CASCADE, ZDBSP),
#           the sanitizer and fuzz tree (clang 14), the style check (clang-format 14), the real
#           models and WADs they read
#   web     the web page's build and tests (Emscripten, node, Chromium)
#   bench   the benchmarks (Google Benchmark; they race the peers of `tests`)
#   all     every one of them (what scripts/test.sh installs)
set -euo pipefail
cli=(build-essential cmake ninja-build pkg-config
     libglm-dev libgmp-dev libassimp-dev zlib1g-dev libcli11-dev libfmt-dev nlohmann-json3-dev
     libtbb-dev libspng-dev libcairo2-dev)
python=(python3 python3-dev pybind11-dev python3-pybind11 python3-numpy)
tests=(libgtest-dev libgmock-dev libstb-dev
       libosmesa6-dev libembree-dev libcgal-dev libpolyclipping-dev libboost-dev assimp-testmodels
       librsvg2-bin libocct-modeling-algorithms-dev libocct-modeling-data-dev
       libocct-visualization-dev
       clang-14 libclang-rt-14-dev clang-format-14
       python3-pytest python3-dask python3-distributed
       freedoom zdbsp)
web=(emscripten nodejs chromium)
bench=(libbenchmark-dev)
purposes=("$@")
[ ${#purposes[@]} -eq 0 ] && purposes=(all)
pkgs=()
for purpose in "${purposes[@]}"; do
  case $purpose in
    cli) pkgs+=("${cli[@]}") ;;
    python) pkgs+=("${cli[@]}" "${python[@]}") ;;
    tests) pkgs+=("${cli[@]}" "${python[@]}" "${tests[@]}") ;;  # the suites test the module too
    web) pkgs+=("${cli[@]}" "${web[@]}") ;;  # the page's tests compare with the native build
    bench) pkgs+=("${cli[@]}" "${python[@]}" "${tests[@]}" "${bench[@]}") ;;
    all) pkgs+=("${cli[@]}" "${python[@]}" "${tests[@]}" "${web[@]}" "${bench[@]}") ;;
    *) echo "install-deps: unknown purpose '$purpose' (cli, python, tests, web, bench, all)" >&2; exit 2 ;;
  esac
done
mapfile -t pkgs < <(printf '%s\n' "${pkgs[@]}" | awk '!seen[$0]++')
missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
echo "install-deps (${purposes[*]}): ${#pkgs[@]} packages, ${#missing[@]} missing"
if [ ${#missing[@]} -gt 0 ]; then
  echo "install-deps: installing ${missing[*]}"
  SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO=sudo
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
