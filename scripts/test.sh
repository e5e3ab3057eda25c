#!/usr/bin/env bash
# Quick start #2: set up, build, and run the whole test suite (CPU core, GPU on lavapipe, CLI).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/build.sh
ctest --test-dir build --output-on-failure -j "$(nproc)"
