#!/usr/bin/env bash
# Runs every libFuzzer target of the build for SECONDS of CPU in all (default 60, split evenly among
# them; they run nproc at a time, so on two cores the stage fuzzes for SECONDS / 2 of wall time):
#   model_fuzzer   model parsing, validation and CPU evaluation (tests/fuzz/model_fuzzer.cpp)
#   merge_fuzzer   shard files of every format through jobs::mergeShards (tests/fuzz/merge_fuzzer.cpp)
#   and any other NAME_fuzzer target the build defines (e.g. eval_at_fuzzer, `eval --at` files).
# Builds with clang into ./build-fuzz (ASan + UBSan + libFuzzer, -O1). Each fuzzer NAME_fuzzer gets its
# own folder build-fuzz/fuzz/NAME/: seeds/ (written by the NAME_fuzz_seeds target when there is one,
# else build-fuzz/fuzz/NAME_seeds/ is used when present), corpus/ (the inputs it finds), artifacts/
# and fuzz.log; tests/fuzz/NAME.dict is its dictionary when present. Any crash, sanitizer report,
# leak or input slower than 5 s fails, and the input is saved under the fuzzer's artifacts/ (replay:
# build-fuzz/tests/fuzz/NAME_fuzzer FILE). Every fuzzer runs even when an earlier one failed.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-60}
root=$PWD

# -O1 -gline-tables-only, what OSS-Fuzz builds fuzzers with: line numbers in every report, and the
# build takes 68 s instead of 97 s on two cores (-O2 -g: 188 s of CPU, now 131 s).
CC=clang CXX=clang++ cmake -S . -B build-fuzz -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -gline-tables-only" \
  -DSHAPESPLINE_FUZZ=ON -DSHAPESPLINE_BUILD_BENCH=OFF >/dev/null

# The fuzz targets and seed writers this tree defines (tolerant of targets added or not yet there).
# (Ninja also lists CMake's own cmake_object_order_depends_target_* phonies: skipped.)
phonies=$(ninja -C build-fuzz -t targets all | sed -n 's/^\([A-Za-z0-9_]*\): phony$/\1/p' | grep -v '^cmake_' | sort -u)
targets=$(sed -n 's/^\([A-Za-z0-9_]*\)_fuzzer$/\1/p' <<<"$phonies")
if [[ -z $targets ]]; then
  echo "fuzz: no *_fuzzer target in build-fuzz" >&2
  exit 1
fi
seeders=$(grep '_fuzz_seeds$' <<<"$phonies" || true)
build=()
for name in $targets; do build+=("${name}_fuzzer"); done
for s in $seeders; do build+=("$s"); done
cmake --build build-fuzz -j "$(nproc)" --target "${build[@]}"
echo "stage: fuzz build $SECONDS s" >&2
# SHAPESPLINE_FUZZ_BUILD_ONLY=1: stop here (scripts/test.sh builds the fuzzers early, in the
# background, and runs this script again to fuzz).
[[ "${SHAPESPLINE_FUZZ_BUILD_ONLY:-0}" == 1 ]] && exit 0

count=$(wc -w <<<"$targets")
per=$((seconds / count))
((per >= 1)) || per=1
parallel=$(nproc)
echo "fuzz: $count fuzzers ($(echo $targets)), ${per} s each, ${parallel} at a time"

export ASAN_OPTIONS="halt_on_error=1:detect_leaks=1:detect_stack_use_after_return=1:${ASAN_OPTIONS:-}"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1:${UBSAN_OPTIONS:-}"

# One fuzzer: its seeds, then `per` seconds of fuzzing. Its seed writer's lines go to seeds.log,
# libFuzzer's progress lines (thousands) to fuzz.log, its exit status to status.
fuzz_one() {
  local name=$1
  local out=build-fuzz/fuzz/$name
  mkdir -p "$out/corpus" "$out/artifacts"
  local folders=("$out/corpus")
  local seeder
  seeder=$(find build-fuzz/tests -name "${name}_fuzz_seeds" -type f -perm -u+x | head -n 1)
  : >"$out/seeds.log"
  if [[ -n $seeder ]]; then
    rm -rf "$out/seeds"
    "$seeder" "$out/seeds" >"$out/seeds.log" 2>&1 || { echo "seed writer failed" >>"$out/seeds.log"; echo 1 >"$out/status"; return; }
    folders+=("$out/seeds")
  elif [[ -d build-fuzz/fuzz/${name}_seeds ]]; then
    folders+=("build-fuzz/fuzz/${name}_seeds")
  fi
  local options=(-max_total_time="$per" -timeout=5 -rss_limit_mb=2048 -max_len=65536
    -artifact_prefix="$out/artifacts/" -print_final_stats=1)
  [[ -f $root/tests/fuzz/$name.dict ]] && options+=(-dict="$root/tests/fuzz/$name.dict")
  # New inputs go to the first folder; the seeds are read only.
  local binary status=0
  binary=$(find build-fuzz/tests -name "${name}_fuzzer" -type f -perm -u+x | head -n 1)
  if [[ -z $binary ]]; then
    echo "no ${name}_fuzzer binary" >"$out/fuzz.log"
    status=1
  else
    "$binary" "${options[@]}" "${folders[@]}" >"$out/fuzz.log" 2>&1 || status=$?
  fi
  echo "$status" >"$out/status"
}

# The fuzzers are independent processes, one core each: nproc of them run at once.
for name in $targets; do
  rm -f "build-fuzz/fuzz/$name/status"
  while (($(jobs -rp | wc -l) >= parallel)); do wait -n || true; done
  fuzz_one "$name" &
done
wait

# The summary of each, in order; on failure the log's tail with the report.
failed=()
for name in $targets; do
  out=build-fuzz/fuzz/$name
  log="$out/fuzz.log"
  cat "$out/seeds.log"
  if [[ $(cat "$out/status" 2>/dev/null) == 0 ]]; then
    grep -E '^(Done|stat::)' "$log" || true
    echo "fuzz: ${name}_fuzzer: no crash, leak, sanitizer report or timeout in ${per} s (log: $log)"
  else
    [[ -f $log ]] && tail -n 200 "$log"
    echo "fuzz: ${name}_fuzzer FAILED (exit $(cat "$out/status" 2>/dev/null || echo none)); inputs in $out/artifacts/" >&2
    failed+=("${name}_fuzzer")
  fi
done
if ((${#failed[@]})); then
  echo "fuzz: FAILED: ${failed[*]}" >&2
  exit 1
fi
echo "fuzz: all $count fuzzers clean, ${per} s each"
