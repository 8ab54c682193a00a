#!/usr/bin/env bash
# Configures and builds hsr. Usage: scripts/build.sh [BUILD_DIR] [extra cmake args...]
# A new build directory uses Ninja (scripts/install-deps.sh installs it): it keeps both cores
# busy across targets and logs every step's time (BUILD_DIR/.ninja_log, which
# scripts/ci-times.sh reads); a directory configured before keeps its generator.
set -euo pipefail
cd "$(dirname "$0")/.."
dir=${1:-build}
shift || true
generator=()
if [ ! -f "$dir/CMakeCache.txt" ] && command -v ninja >/dev/null; then generator=(-G Ninja); fi
cmake -S . -B "$dir" "${generator[@]}" -DCMAKE_BUILD_TYPE=Release "$@" >/dev/null
cmake --build "$dir" -j"$(nproc)"
