#!/usr/bin/env bash
# Configures and builds into ./build (Release), tests and benchmarks included (also after
# scripts/demo.sh configured the folder without them). Extra arguments go to CMake's configure step.
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DSHAPESPLINE_BUILD_TESTS=ON -DSHAPESPLINE_BUILD_BENCH=ON "$@" \
  >/dev/null
cmake --build build -j "$(nproc)"
