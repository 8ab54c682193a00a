#!/usr/bin/env bash
# The web page's tests, run by scripts/test.sh after the native Release suite (whose hsr they
# compare with): the page built (scripts/build-web.sh); the web module against the native
# `hsr render` and `hsr explain`, byte for byte (web/test/node_test.mjs); the GoogleTest files
# that need only the core, built to WebAssembly and run under node; the page in headless
# Chromium, its canvases against the native PNGs (web/test/browser_test.mjs), with a screenshot
# kept in build-wasm/artifacts/page.png. Usage: scripts/test-web.sh [NATIVE_HSR] (default build/hsr)
set -euo pipefail
cd "$(dirname "$0")/.."
native=${1:-build/hsr}
# The module and the tests built in one make (their links run on one core each, beside the
# other's compiles); build-web.sh then finds the module built and makes the site
cmake --preset wasm >/dev/null
cmake --build --preset wasm --target hsr_web_and_tests
scripts/build-web.sh build-wasm/site
echo "== the web module against the native build =="
node web/test/node_test.mjs build-wasm/web "$native" build-wasm/node-test
echo "== GoogleTest under node (the core as WebAssembly), in two halves side by side =="
# node runs one thread: the suites are split in two (a filter and its complement, so that every
# test runs exactly once), one node process on each core (by the suites' times in the last CI log, about 52 s each)
first="RasterProperties.*:ConformanceNearPlane.*:Bvh.*:Predicates.*:Degenerate.*"
(cd build-wasm/web && node hsr_wasm_tests.js --gtest_filter="$first" > ../gtest-1.log 2>&1) & one=$!
(cd build-wasm/web && node hsr_wasm_tests.js --gtest_filter="-$first" > ../gtest-2.log 2>&1) & two=$!
rc=0
wait $one || rc=1
wait $two || rc=1
cat build-wasm/gtest-1.log build-wasm/gtest-2.log
[ $rc -eq 0 ] || { echo "test-web: GoogleTest under node failed"; exit 1; }
grep -h "tests\? ran\|PASSED" build-wasm/gtest-1.log build-wasm/gtest-2.log
echo "== the page in headless Chromium =="
node web/test/browser_test.mjs build-wasm/site "$native" build-wasm/artifacts
