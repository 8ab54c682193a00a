#!/usr/bin/env bash
# Installs the Debian packages hsr builds, tests and benchmarks with. Idempotent.
set -euo pipefail
pkgs=(build-essential cmake ninja-build pkg-config
      libglm-dev libgmp-dev libassimp-dev zlib1g-dev libcli11-dev libfmt-dev nlohmann-json3-dev libtbb-dev libstb-dev libspng-dev
      libgtest-dev libgmock-dev libbenchmark-dev
      libosmesa6-dev libembree-dev libcgal-dev libpolyclipping-dev libboost-dev assimp-testmodels
      librsvg2-bin libcairo2-dev libocct-modeling-algorithms-dev libocct-modeling-data-dev
      libocct-visualization-dev
      clang-14 libclang-rt-14-dev
      python3 python3-dev pybind11-dev python3-pybind11 python3-numpy python3-pytest python3-dask
      python3-distributed
      freedoom zdbsp
      emscripten nodejs chromium)
missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  echo "install-deps: installing ${missing[*]}"
  SUDO=""; [ "$(id -u)" -ne 0 ] && SUDO=sudo
  $SUDO apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi
