#!/usr/bin/env bash
# Configures and builds into ./build (Release), every test and benchmark included (also after
# scripts/demo.sh or scripts/test.sh configured the folder with fewer). Extra arguments go to CMake's
# configure step.
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DSHAPESPLINE_BUILD_TESTS=ON -DSHAPESPLINE_BUILD_BENCH=ON \
  -DSHAPESPLINE_RELEASE_STAGE_TESTS=OFF "$@" \
  >/dev/null
cmake --build build -j "$(nproc)"
