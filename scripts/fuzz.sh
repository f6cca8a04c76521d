#!/usr/bin/env bash
# Fuzzes the parsers that read user files (TUM image lists + association, association files, TUM trajectories,
# YAML configs, map files, the detector model's ONNX graph as our SiLU fusion reads it) with libFuzzer + ASan +
# UBSan (+ LeakSanitizer), using Debian's clang.
#   scripts/fuzz.sh          # 600 s per target (the issue-7 soak; ~30 min in all)
#   scripts/fuzz.sh 30       # the short run CI does
# Seeds: fuzz/corpus/<target>/ (heads of real TUM files, the shipped configs) plus every input in
# fuzz/regressions/<target>/. A crash, leak, hang (>10 s per input) or uncaught exception fails the
# script; the input that caused it is copied to fuzz/regressions/<target>/, where the unit test
# FuzzRegression.* replays it from then on.
set -euo pipefail
cd "$(dirname "$0")/.."
SECONDS_PER_TARGET=${1:-600}
DIR=build-fuzz
if ! command -v clang++ > /dev/null; then
  echo "fuzz.sh: clang++ not found (apt-get install clang libclang-rt-14-dev)" >&2
  exit 2
fi
CC=clang CXX=clang++ cmake -S . -B "$DIR" -DCMAKE_BUILD_TYPE=RelWithDebInfo -DTKGSLAM_BUILD_FUZZERS=ON \
  -DTKGSLAM_BUILD_TESTS=OFF -DTKGSLAM_BUILD_BENCH=OFF > /dev/null
cmake --build "$DIR" -j"$(nproc)"
export ASAN_OPTIONS=detect_leaks=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
status=0
for pair in TumLists:tum_lists Trajectory:trajectory Config:config MapFile:map_file OnnxGraph:onnx_graph; do
  target=${pair%%:*}; name=${pair##*:}
  work="$DIR/corpus/$name"; artifacts="$DIR/artifacts/$name/"
  mkdir -p "$work" "$artifacts" "fuzz/regressions/$name"
  echo "== fuzz_$target: ${SECONDS_PER_TARGET} s"
  if ! "$DIR/fuzz/fuzz_$target" -max_total_time="$SECONDS_PER_TARGET" -timeout=10 -rss_limit_mb=2048 \
      -max_len=4096 -print_final_stats=1 -artifact_prefix="$artifacts" \
      "$work" "fuzz/corpus/$name" "fuzz/regressions/$name" > "$DIR/$name.log" 2>&1; then
    tail -n 40 "$DIR/$name.log"
    for f in "$artifacts"*; do
      [ -f "$f" ] && cp "$f" "fuzz/regressions/$name/" && echo "kept $f as fuzz/regressions/$name/$(basename "$f")"
    done
    status=1
  else
    grep -E "^stat::number_of_executed_units|^stat::peak_rss_mb" "$DIR/$name.log" | tr '\n' ' '; echo
  fi
done
[ "$status" = 0 ] && echo "fuzz: no crash, leak or hang"
exit $status
