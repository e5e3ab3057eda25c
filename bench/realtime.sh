#!/usr/bin/env bash
# The real-time adaptive frame (issue 18): shapespline_realtime_bench (bench/realtime/main.cpp) on
# the default Vulkan device. One run measures, for the 1,000-patch α-EB surface at 1280x720 with an
# orbiting camera and a 1 px tolerance: adaptive triangles against the uniform rate of equal error,
# the adaptive frame (rates + tessellation; and with the draw), our fixed-rate tessellator and
# OpenSubdiv's Bfr (2 threads) at that uniform rate, and the pop of rate changes with and without
# hysteresis. Prints the table and writes bench/results/realtime.json.
#
# Environment: BUILD_DIR (default build-bench), FRAMES (default 120), REPS (default 5),
# TOLERANCE (default 1), THREADS (default 2, Bfr's).
set -euo pipefail
root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
cd "$root"
build=${BUILD_DIR:-build-bench}
if [[ ! -f $build/build.ninja ]]; then
  cmake -S . -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DSHAPESPLINE_BUILD_BENCH=ON >/dev/null
fi
cmake --build "$build" --target shapespline_realtime_bench -j"${JOBS:-2}" >/dev/null
mkdir -p bench/results
echo "load average before: $(cut -d' ' -f1-3 /proc/loadavg)" >&2
"$build/bench/shapespline_realtime_bench" --frames "${FRAMES:-120}" --reps "${REPS:-5}" \
  --tolerance "${TOLERANCE:-1}" --threads "${THREADS:-2}" --json bench/results/realtime.json
echo "load average after: $(cut -d' ' -f1-3 /proc/loadavg)" >&2
