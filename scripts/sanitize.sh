#!/usr/bin/env bash
# Builds the project with AddressSanitizer + UndefinedBehaviorSanitizer into ./build-asan (gcc, -O1;
# the test code itself -Og, which compiles in half the time; no benchmarks) and runs the gtest
# executables there (scripts/test_sets.sh: all but the peak-RSS tests). Any ASan/UBSan report or
# leak fails the run (tests/support/lsan.supp documents why it suppresses nothing).
#
# The test executables run as a few gtest shards each (GTEST_TOTAL_SHARDS), not one process per
# test as ctest does: under ASan process start-up dominates, and one process per executable took the
# stage from ~8 min to ~1 min on two cores. The shards run $(nproc) at a time: cli_tests alone ran
# 515 s in one process (CI, two cores), most of it in the ASan-built shapespline it runs; split in
# shards it uses both cores. gpu_tests is the exception, one process started first: its tests share
# the process's Vulkan context, whose pipelines lavapipe compiles once per process, slowly under
# ASan's allocator (its process time: 296 s in 4 shards, 251 s in 2, 215 s in 1). Every test still
# runs exactly once. ctest runs the fuzz seed replay (unless SHAPESPLINE_REPLAY_FUZZ_SEEDS=0).
set -euo pipefail
cd "$(dirname "$0")/.."
root=$PWD
source scripts/test_sets.sh

cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -g1" \
  -DSHAPESPLINE_SANITIZE=ON -DSHAPESPLINE_BUILD_BENCH=OFF -DSHAPESPLINE_TEST_CXX_FLAGS=-Og >/dev/null

# Builds only what runs below (not `all`: not the examples, nor anything else it does not run): the test
# executables (cli_tests depends on the shapespline CLI it runs) and the programs of the fuzz
# replay tests, read from the CTestTestfile.cmake files (ctest -N shows no path for a program not
# built yet; tolerant of fuzzers added or not yet there).
# Longest process first (gpu_tests, then the shards of cli_tests), for the shard pool below.
executables=("${sanitized_gtests[@]}")
phonies=$(ninja -C build-asan -t targets all | sed -n 's/^\([A-Za-z0-9_]*\): phony$/\1/p' | sort -u)
targets=(shapespline_keep_libraries_loaded)
for exe in "${executables[@]}"; do
  if grep -qx "$exe" <<<"$phonies"; then targets+=("$exe"); fi
done
# SHAPESPLINE_REPLAY_FUZZ_SEEDS=0 (scripts/test.sh, when its fuzz stage follows): no replay here, as
# every fuzzer starts by running its seeds under ASan + UBSan (clang) there.
replay=${SHAPESPLINE_REPLAY_FUZZ_SEEDS:-1}
if [[ $replay == 1 ]]; then
  for program in $(find build-asan -name CTestTestfile.cmake -exec \
      sed -n 's/^add_test(\[=\[fuzz\/[^]]*\]=\] "\([^"]*\)".*/\1/p' {} +); do
    name=$(basename "$program")
    if grep -qx "$name" <<<"$phonies"; then targets+=("$name"); fi
  done
fi
cmake --build build-asan -j "$(nproc)" --target "${targets[@]}"
echo "stage: sanitizers build $SECONDS s" >&2
built=$SECONDS

# The Vulkan loader dlclose()s its driver and layers; LeakSanitizer would then report memory they
# still referenced as "<unknown module>" leaks. Every process preloads a dlclose() that keeps
# libraries loaded (tests/sanitizer/keep_libraries_loaded.cpp; it is loaded before the ASan runtime,
# hence verify_asan_link_order=0).
keep="$root/build-asan/tests/libshapespline_keep_libraries_loaded.so"
# The processes that enable the validation layer (the test fixture's instances: every test
# executable but cli_tests, whose CLI runs do not) preload it too: its thread_local state then lives
# in static TLS, which LeakSanitizer scans. Opened by the loader, the layer's TLS is dynamic and
# unscanned, and four allocations of lavapipe and the loader that only the layer still points to
# are reported as leaked. The CLI's processes, thousands of them, start without it (0.06 s each).
layer=$(sed -n 's/.*"library_path": *"\([^"]*\)".*/\1/p' \
  /usr/share/vulkan/explicit_layer.d/VkLayer_khronos_validation.json 2>/dev/null | head -n 1)
[[ -z $layer || $layer == /* ]] || layer=$(ldconfig -p | sed -n "s|.*$layer[^/]*=> \(.*\)|\1|p" | head -n 1)
preload_for() {  # EXE: the LD_PRELOAD its processes start with
  local list=$keep
  [[ $1 != cli_tests && -n $layer && -f $layer ]] && list+=" $layer"
  echo "$list${LD_PRELOAD:+ $LD_PRELOAD}"
}
# Only lavapipe where it is installed (VK_ICD_FILENAMES): the sanitizers check our code; lavapipe is
# the device CI has, and the loader then opens no other driver.
lavapipe=(/usr/share/vulkan/icd.d/lvp_icd.*.json)
if [[ -f ${lavapipe[0]} ]]; then
  export VK_ICD_FILENAMES=${lavapipe[0]}
fi

# quarantine_size_mb=64 (default 256): freed memory is held back 64 MB deep before reuse, which still
# catches a use after free anywhere near its free. lavapipe allocates and frees large blocks for every
# dispatch; with 256 MB of them held, each new one came from fresh pages, and VkContextTest's
# PassTimerTimesEachPass took 25.6 s (64 MB: 8.7 s; 16 MB: 2.8 s; 0.6 s without ASan).
export ASAN_OPTIONS="halt_on_error=1:detect_leaks=1:detect_stack_use_after_return=1:check_initialization_order=1:strict_init_order=1:verify_asan_link_order=0:quarantine_size_mb=64:${ASAN_OPTIONS:-}"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1:${UBSAN_OPTIONS:-}"
export LSAN_OPTIONS="suppressions=$root/tests/support/lsan.supp:${LSAN_OPTIONS:-}"

failed=()
parallel=$(nproc)
shards_of() {  # EXE: how many gtest shards it runs as
  if [[ $1 == gpu_tests ]]; then echo 1; else echo $((2 * parallel)); fi  # the pool stays busy to the end
}
logs=build-asan/sanitize-logs
rm -rf "$logs"
mkdir -p "$logs"
ran=()
for exe in "${executables[@]}"; do
  [[ -x build-asan/tests/$exe ]] || continue
  ran+=("$exe")
  shards=$(shards_of "$exe")
  for ((i = 0; i < shards; i++)); do
    while (($(jobs -rp | wc -l) >= parallel)); do wait -n || true; done
    # From the repository root, like ctest. Each shard's exit status goes to its .rc file.
    (
      status=0
      LD_PRELOAD=$(preload_for "$exe") GTEST_TOTAL_SHARDS=$shards GTEST_SHARD_INDEX=$i \
        build-asan/tests/$exe --gtest_brief=1 \
        --gtest_output="xml:$logs/$exe.$i.xml" >"$logs/$exe.$i.log" 2>&1 || status=$?
      echo "$status" >"$logs/$exe.$i.rc"
    ) &
  done
done
wait
for exe in "${ran[@]}"; do
  shards=$(shards_of "$exe")
  echo "sanitize: $exe ($shards shards)" >&2
  for ((i = 0; i < shards; i++)); do
    cat "$logs/$exe.$i.log"
    if [[ $(cat "$logs/$exe.$i.rc" 2>/dev/null) != 0 ]]; then
      echo "sanitize: $exe shard $i of $shards FAILED (log: $logs/$exe.$i.log)" >&2
      [[ " ${failed[*]} " == *" $exe "* ]] || failed+=("$exe")
    fi
  done
done
if [[ $replay == 1 ]]; then
  LD_PRELOAD=$(preload_for fuzz) ctest --test-dir build-asan --output-on-failure -j "$(nproc)" -R '^fuzz/' ||
    failed+=("fuzz replay")
fi
# Where the stage's time went: the ten slowest tests (gtest's own times, from the shards' reports).
cat "$logs"/*.xml 2>/dev/null |
  sed -n 's/.*<testcase name="\([^"]*\)".* time="\([0-9.]*\)".* classname="\([^"]*\)".*/\2 \3.\1/p' |
  sort -rn | head -n 10 | sed 's/^/sanitize: slowest: /' >&2 || true
echo "stage: sanitizers run $((SECONDS - built)) s" >&2
if ((${#failed[@]} > 0)); then
  echo "sanitize: failures in ${failed[*]}" >&2
  exit 1
fi
