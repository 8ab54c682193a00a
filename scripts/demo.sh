#!/usr/bin/env bash
# Quick start: install what is needed, build in Release, render the built-in demo scene.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh build -DHSR_BUILD_TESTS=OFF -DHSR_BUILD_BENCH=OFF
./build/hsr render demo --outline -o out/demo.png "$@"
