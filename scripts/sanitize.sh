#!/usr/bin/env bash
# Builds the project with AddressSanitizer + UndefinedBehaviorSanitizer into ./build-asan (gcc, -O1,
# no benchmarks) and runs the whole test suite there. Any ASan/UBSan report or leak fails the run
# (tests/support/lsan.supp documents why it suppresses nothing).
#
# The test executables run once each (not one process per test as ctest does): under ASan process
# start-up dominates, and one process per executable takes the stage from ~8 min to ~1 min on two
# cores. ctest still runs the tests registered without gtest (the fuzz seed replay).
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD

cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g1" \
  -DSHAPESPLINE_SANITIZE=ON -DSHAPESPLINE_BUILD_BENCH=OFF >/dev/null
cmake --build build-asan -j "$(nproc)"

# The Vulkan loader dlclose()s drivers and layers; LeakSanitizer then reports memory they still
# referenced as "<unknown module>" leaks. Preloading them keeps them mapped (the ASan runtime is then
# not first in the library list, hence verify_asan_link_order=0).
preload=()
for manifest in /usr/share/vulkan/icd.d/*.json /usr/share/vulkan/implicit_layer.d/*.json \
  /usr/share/vulkan/explicit_layer.d/VkLayer_khronos_validation.json; do
  [[ -f $manifest ]] || continue
  lib=$(sed -n 's/.*"library_path": *"\([^"]*\)".*/\1/p' "$manifest" | head -n 1)
  [[ $lib == /* ]] || lib=$(ldconfig -p | sed -n "s|.*$lib[^/]*=> \(.*\)|\1|p" | head -n 1)
  if [[ -n $lib && -f $lib ]]; then preload+=("$lib"); fi
done
export LD_PRELOAD="${preload[*]}${LD_PRELOAD:+ $LD_PRELOAD}"

export ASAN_OPTIONS="halt_on_error=1:detect_leaks=1:detect_stack_use_after_return=1:check_initialization_order=1:strict_init_order=1:verify_asan_link_order=0:${ASAN_OPTIONS:-}"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1:${UBSAN_OPTIONS:-}"
export LSAN_OPTIONS="suppressions=$root/tests/support/lsan.supp:${LSAN_OPTIONS:-}"

# GpuStreamLarge.JobStreamsInBoundedMemory and MemoryBoundRss.* (cli_tests: the peak RSS of an
# ASan-built shapespline) measure peak RSS, which ASan's quarantine and shadow memory inflate by
# hundreds of MiB: they run in the normal build only.
excluded="GpuStreamLarge.JobStreamsInBoundedMemory:MemoryBoundRss.*"
failed=()
for exe in core_tests io_tests gpu_tests sampling_tests cli_tests; do
  [[ -x build-asan/tests/$exe ]] || continue
  echo "sanitize: $exe" >&2
  # From the repository root, like ctest.
  build-asan/tests/$exe --gtest_brief=1 --gtest_filter="-$excluded" || failed+=("$exe")
done
ctest --test-dir build-asan --output-on-failure -j "$(nproc)" -R '^fuzz/' || failed+=("fuzz replay")
if ((${#failed[@]} > 0)); then
  echo "sanitize: failures in ${failed[*]}" >&2
  exit 1
fi
