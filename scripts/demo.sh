#!/usr/bin/env bash
# Quick start #1: installs what the demo needs, builds only the shapespline command (no tests,
# benchmarks or Python module) and runs `shapespline demo`: example models, their samples (OBJ, SVG)
# and a rendered contact sheet (PNG) in ./shapespline-demo/. `scripts/test.sh` later builds the rest
# into the same build folder, reusing what this compiled.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh --demo
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DSHAPESPLINE_BUILD_TESTS=OFF -DSHAPESPLINE_BUILD_BENCH=OFF >/dev/null
cmake --build build -j "$(nproc)" --target shapespline
./build/host/cli/shapespline demo "$@"
