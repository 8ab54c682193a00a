#!/usr/bin/env bash
# Quick start: install what the hsr command needs (scripts/install-deps.sh cli: 14 packages, not
# the test suites' peers, the web build's toolchain or the Python module's), build it in Release,
# render the built-in demo scene.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh cli
scripts/build.sh build -DHSR_BUILD_TESTS=OFF -DHSR_BUILD_BENCH=OFF -DHSR_BUILD_PYTHON=OFF
./build/hsr render demo --outline -o out/demo.png "$@"
