#!/usr/bin/env bash
# Dynamic benchmark from real data (issue 5): composites of real people walking through the real
# fr1_xyz sequence, every ablation mode on each and on the static original, tables like the
# paper's Tables 1-4 in OUT/tables.md.
#   bench/dynamic_benchmark.sh [OUT]        env: FRAMES (default 300), MODES, SEQ, ONLY (sequence names to
#                                           (re)run, e.g. "static high"; default all), SEEDS, SEEDED,
#                                           JOBS (runs at a time, default 1), TKGSLAM_BIN (the CLI to run),
#                                           SET (config overrides for every run, e.g. "dynamic.max_age=5
#                                           loop.enabled=false": each one is a `run --set`; no spaces in a value)
# Every run uses --deterministic, so one run per cell is the median of any number of runs. What a
# single composite cannot show is how much a difference between modes depends on where the people
# happen to walk: SEEDS="22 32" adds replicas of the SEEDED composites (default "high very_high high_blur high_shake extreme")
# built with those seeds (named e.g. high_s22), and the tables get their mean and spread.
# JOBS=2 runs two at a time: the same trajectories and accuracy tables (the runs are deterministic) in
# about half the time, but the runs share the cores, so the time table's multiples of T come out inflated.
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
BIN=${TKGSLAM_BIN:-"$ROOT/build/bin/tkgslam"}
SEQ=${SEQ:-"$ROOT/../shared/datasets/rgbd_dataset_freiburg1_xyz"}
PEOPLE=${PEOPLE:-"$ROOT/../shared/datasets/people"}
OUT=${1:-"$ROOT/out/dynamic_benchmark"}
FRAMES=${FRAMES:-300}
JOBS=${JOBS:-1}
[[ "$JOBS" =~ ^[1-9][0-9]*$ ]] || { echo "JOBS must be a positive whole number, not '$JOBS'" >&2; exit 2; }
MODES=${MODES:-"orb T TK TG TKG TKGp TKGa TKGl TKGt TKGf"}   # TKGp: the paper's TKG; TKGa/l/t/f: asynchronous detector (see run_one)
CFG="$ROOT/configs/tum_fr1.yaml"
# shellcheck source=bench/modes.sh
source "$ROOT/bench/modes.sh"
[ -x "$BIN" ] || { echo "build first: scripts/build.sh" >&2; exit 1; }
[ -d "$SEQ" ] || { echo "sequence $SEQ not found" >&2; exit 1; }
for mode in $MODES; do
  mode_flags "$mode" || { echo "unknown mode '$mode' (modes: orb T TK TG TKG TKGp TKGa TKGl TKGt TKGf TKGs)" >&2; exit 2; }
done
mkdir -p "$OUT"

# name | augment options
COMPOSITES=(
  "low|--count 1 --min-size 0.25 --max-size 0.4 --speed 0.15 --seed 11"
  "high|--count 3 --min-size 0.6 --max-size 0.95 --speed 0.4 --seed 12"
  "very_high|--count 3 --min-size 0.75 --max-size 1.0 --speed 0.4 --seed 14"
  "high_blur|--count 3 --min-size 0.6 --max-size 0.95 --speed 0.4 --blur 0.3 --blur-people --seed 13"
  "high_shake|--count 3 --min-size 0.6 --max-size 0.95 --speed 0.4 --blur 0.3 --seed 13"
  "extreme|--count 4 --min-size 0.8 --max-size 1.1 --speed 0.4 --seed 12"
)
SEEDED=${SEEDED:-"high very_high high_blur high_shake extreme"}
for c in "${COMPOSITES[@]}"; do
  name=${c%%|*}; opts=${c#*|}
  [[ " $SEEDED " == *" $name "* ]] || continue
  for seed in ${SEEDS:-}; do COMPOSITES+=("${name}_s$seed|${opts% --seed *} --seed $seed"); done
done
ONLY=${ONLY:-"static ${COMPOSITES[*]%%|*}"}
selected() { [[ " $ONLY " == *" $1 "* ]]; }
for c in "${COMPOSITES[@]}"; do
  name=${c%%|*}; opts=${c#*|}
  selected "$name" || continue  # only the composites that will be run
  if [ ! -f "$OUT/seq_$name/rgb.txt" ]; then
    echo "== building composite '$name' ($FRAMES frames)"
    # shellcheck disable=SC2086
    "$BIN" augment -c "$CFG" -d "$SEQ" -p "$PEOPLE" -o "$OUT/seq_$name" --frames "$FRAMES" $opts | tee "$OUT/seq_$name.log"
  fi
done

OVERRIDES=()  # SET as `run --set` arguments: split on spaces, no glob expansion ("[0,1]" is a YAML list)
read -r -a set_items <<< "${SET:-}"
for kv in ${set_items[@]+"${set_items[@]}"}; do OVERRIDES+=(--set "$kv"); done

run_one() {  # sequence-name dataset-dir mode
  local name=$1 dir=$2 mode=$3 res="$OUT/runs/$1/$3"
  mode_flags "$mode"  # checked at the start
  mkdir -p "$res"
  echo "== $name / $mode"
  if ! "$BIN" run -q --deterministic -c "$CFG" -d "$dir" -o "$res" "${MODE_FLAGS[@]}" ${OVERRIDES[@]+"${OVERRIDES[@]}"} \
      --max-frames "$FRAMES" > "$res/run.log" 2>&1; then
    echo "run failed: $name / $mode: $(tail -n 1 "$res/run.log") (see $res/run.log)" >&2
    return 1
  fi
  "$BIN" eval --json --frames "$dir" "$dir/groundtruth.txt" "$res/trajectory.txt" > "$res/eval.json" 2> "$res/eval.err" ||
    echo '{}' > "$res/eval.json"
}
RUNS=()  # sequence-name|dataset-dir|mode
if selected static; then for mode in $MODES; do RUNS+=("static|$SEQ|$mode"); done; fi
for c in "${COMPOSITES[@]}"; do
  name=${c%%|*}
  selected "$name" || continue
  for mode in $MODES; do RUNS+=("$name|$OUT/seq_$name|$mode"); done
done
failed="$OUT/.failed_runs"
rm -f "$failed"
for r in "${RUNS[@]}"; do
  IFS='|' read -r name dir mode <<< "$r"
  if [ "$JOBS" -eq 1 ]; then
    run_one "$name" "$dir" "$mode"
  else
    while [ "$(jobs -rp | wc -l)" -ge "$JOBS" ]; do wait -n || true; done
    { run_one "$name" "$dir" "$mode" || echo "$name / $mode" >> "$failed"; } &
  fi
done
wait
if [ -f "$failed" ]; then
  echo "$(wc -l < "$failed") run(s) failed: $(paste -sd, "$failed")" >&2
  exit 1
fi
python3 "$ROOT/bench/make_tables.py" "$OUT" "$FRAMES" > "$OUT/tables.md"
if [ -n "${SET:-}" ]; then
  printf '\n%s\n' "Config overrides of every run (SET, each a \`run --set\`): ${SET}" >> "$OUT/tables.md"
fi
if [ "$JOBS" -gt 1 ]; then
  printf '\n%s\n' "Timing: these runs went $JOBS at a time, sharing the machine's cores: the multiples of T above are inflated (JOBS=1 for timing)." >> "$OUT/tables.md"
fi
echo "tables: $OUT/tables.md, figure: $OUT/precision_recall.svg"
