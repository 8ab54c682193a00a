#!/usr/bin/env bash
# Builds the web page: hsr's core and the page's module as WebAssembly with Debian's Emscripten
# (CMakePresets.json, preset "wasm", into build-wasm/), then the page itself into a folder any
# static server can host. Usage: scripts/build-web.sh [SITE_DIR] (default out/web).
# Open it locally with: python3 -m http.server --directory out/web 8000, then
# http://localhost:8000/
set -euo pipefail
cd "$(dirname "$0")/.."
site=${1:-out/web}
cmake --preset wasm >/dev/null
cmake --build --preset wasm --target hsr_web
mkdir -p "$site"
cp web/index.html web/app.js web/hsr.js web/style.css build-wasm/web/hsr_web.js build-wasm/web/hsr_web.wasm "$site"/
echo "build-web: the page is in $site ($(du -sh "$site" | cut -f1)); open it with"
echo "  python3 -m http.server --directory $site 8000   and http://localhost:8000/"
