#!/usr/bin/env bash
# Runs every fuzz target (or those $TARGETS names) for a bounded time on the nightly toolchain,
# from a seed corpus of the example genera, scenes and animate arguments (renamed to the fuzzed
# file's name), with a dictionary of the files' keys. Prints executions, time and findings per target; exits non-zero if any target found a
# crash. Needs `cargo install cargo-fuzz`.
#
#   fuzz/run.sh                                  # 2 minutes per target, one worker
#   PARSER_SECONDS=420 CODEGEN_SECONDS=240 JOBS=2 fuzz/run.sh
set -euo pipefail
cd "$(dirname "$0")"
parser_seconds=${PARSER_SECONDS:-${SECONDS_PER_TARGET:-120}}
codegen_seconds=${CODEGEN_SECONDS:-${SECONDS_PER_TARGET:-120}}
jobs=${JOBS:-1}
root=..
mkdir -p corpus/genus corpus/scene
for f in "$root"/examples/genera/*.toml "$root"/examples/custom/*.toml; do
  n=$(basename "$f" .toml)
  sed "s/^name = \"$n\"/name = \"fuzzed\"/" "$f" > "corpus/genus/$n.toml"
done
for f in "$root"/examples/scenes/*.toml "$root"/examples/views/*.toml; do
  n=$(basename "$f" .toml)
  sed "s/^name = \"$n\"/name = \"fuzzed\"/; s/^genus = \".*\"/genus = \"fuzzed\"/" "$f" > "corpus/scene/$n.toml"
done
# Timelines and packages: the example scenes as they are (their genera are the examples'),
# each behind the byte that picks the time (and the engine).
mkdir -p corpus/timeline corpus/animate
for f in "$root"/examples/scenes/*.toml; do
  n=$(basename "$f" .toml)
  { printf '\x07'; sed "s/^name = \"$n\"/name = \"fuzzed\"/" "$f"; } > "corpus/timeline/$n.toml"
done
printf 'day-with-wind.toml\n--to\n7200\n--speed\n1800\n--fps\n1' > corpus/animate/day.args
printf 'clouds-forming.toml\n--to\n600\n--speed\n300\n--fps\n1' > corpus/animate/forming.args
printf 'sunset.toml\n--to\n0' > corpus/animate/sunset.args
targets=${TARGETS:-genus_parser scene_parser genus_codegen scene_codegen timeline animate_args engine_package}
status=0
report=""
for target in $targets; do
  case $target in
    genus_*) corpus=corpus/genus ;;
    timeline | engine_package) corpus=corpus/timeline ;;
    animate_args) corpus=corpus/animate ;;
    *) corpus=corpus/scene ;;
  esac
  case $target in
    *_parser | timeline | animate_args) per=$parser_seconds ;;
    *) per=$codegen_seconds ;;
  esac
  # engine_package makes the package's noise textures once on the GPU (lavapipe here); the
  # Vulkan driver keeps 128 bytes it never frees, which LeakSanitizer reports at exit from the
  # driver's module (no Nimbus frame in the stack). Leaks are not what this target looks for.
  # (-detect_leaks=0 for libFuzzer's runs, ASAN_OPTIONS for the check at exit.)
  case $target in
    engine_package) extra=-detect_leaks=0 asan=detect_leaks=0 ;;
    *) extra= asan=${ASAN_OPTIONS:-} ;;
  esac
  mkdir -p "work/$target"
  log="work/$target.log"
  rm -f fuzz-*.log
  start=$(date +%s)
  if ASAN_OPTIONS=$asan cargo +nightly fuzz run "$target" "work/$target" "$corpus" -- \
      -max_total_time="$per" -dict=nimbus.dict -jobs="$jobs" -workers="$jobs" \
      -print_final_stats=1 $extra > "$log" 2>&1; then
    found=0
  else
    found=1
    status=1
  fi
  took=$(( $(date +%s) - start ))
  # With JOBS > 1 each worker's statistics are in its fuzz-N.log (and echoed in the main log);
  # count each worker once.
  if ls fuzz-*.log >/dev/null 2>&1; then counted=(fuzz-*.log); else counted=("$log"); fi
  execs=$(grep -h "stat::number_of_executed_units" "${counted[@]}" | awk '{s+=$2} END {print s+0}')
  cat fuzz-*.log >> "$log" 2>/dev/null || true
  rm -f fuzz-*.log
  report+="$target: $execs executions in ${took} s, $( [ $found = 0 ] && echo 'no crash' || echo "CRASH (see $log and artifacts/$target)")"$'\n'
done
printf '%s' "$report"
exit $status
