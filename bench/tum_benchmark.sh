#!/usr/bin/env bash
# Runs tkgslam on real TUM RGB-D sequences in several modes and writes the paper's tables (ATE, RPE,
# tracked frames, time per frame) next to the published numbers of the TKG-SLAM paper.
#   bench/tum_benchmark.sh [-o OUT] DIR...
# Each DIR is a TUM sequence folder (with rgb.txt) or a folder holding such sequences, e.g. the
# unpacked rgbd_dataset_freiburg3_walking_xyz, ... The config follows the folder name (freiburg1/2/3 ->
# configs/tum_fr1/2/3.yaml) unless CONFIG is set. Env: MODES (default "orb T TKG TKGf"; any of
# bench/modes.sh), FRAMES (first N frames only; default all), FORCE=1 (rerun runs that are already
# done; by default a finished run - OUT/runs/SEQ/MODE/run.json - is kept, so an interrupted
# benchmark resumes), TKGSLAM_BIN (the CLI to run; default build/bin/tkgslam). Every run uses
# --deterministic. Tables: OUT/tables.md.
set -euo pipefail
ROOT=$(cd "$(dirname "$0")/.." && pwd)
BIN=${TKGSLAM_BIN:-"$ROOT/build/bin/tkgslam"}  # TKGSLAM_BIN: another build of the CLI
# shellcheck source=bench/modes.sh
source "$ROOT/bench/modes.sh"
OUT="$ROOT/out/tum_benchmark"
usage() { echo "usage: bench/tum_benchmark.sh [-o OUT] DIR...  (TUM sequence folders, or folders holding them)" >&2; exit 2; }
while getopts "o:h" opt; do
  case "$opt" in
    o) OUT=$OPTARG ;;
    *) usage ;;
  esac
done
shift $((OPTIND - 1))
[ $# -gt 0 ] || usage
MODES=${MODES:-"orb T TKG TKGf"}
FRAMES=${FRAMES:-0}
[[ "$FRAMES" =~ ^[0-9]+$ ]] || { echo "FRAMES must be a whole number, got '$FRAMES'" >&2; exit 2; }
[ -x "$BIN" ] || { echo "build first: scripts/build.sh" >&2; exit 2; }
for mode in $MODES; do
  mode_flags "$mode" || { echo "unknown mode '$mode' (modes: orb T TK TG TKG TKGp TKGa TKGl TKGt TKGf TKGs)" >&2; exit 2; }
done
if [ -n "${CONFIG:-}" ] && [ ! -f "$CONFIG" ]; then echo "CONFIG: no such file: $CONFIG" >&2; exit 2; fi

# The sequences: each argument itself, or the sequence folders directly inside it.
SEQS=()
for arg in "$@"; do
  [ -d "$arg" ] || { echo "not a folder: $arg" >&2; exit 2; }
  if [ -f "$arg/rgb.txt" ]; then
    SEQS+=("$(cd "$arg" && pwd)")
  else
    found=0
    for d in "$arg"/*/; do
      [ -f "$d/rgb.txt" ] && { SEQS+=("$(cd "$d" && pwd)"); found=1; }
    done
    [ "$found" = 1 ] || { echo "no TUM sequence (a folder with rgb.txt) in $arg" >&2; exit 2; }
  fi
done

config_for() {  # sequence folder -> config file
  if [ -n "${CONFIG:-}" ]; then echo "$CONFIG"; return; fi
  case "$(basename "$1")" in
    *freiburg1*) echo "$ROOT/configs/tum_fr1.yaml" ;;
    *freiburg2*) echo "$ROOT/configs/tum_fr2.yaml" ;;
    *freiburg3*) echo "$ROOT/configs/tum_fr3.yaml" ;;
    *) return 1 ;;
  esac
}
for dir in "${SEQS[@]}"; do
  config_for "$dir" > /dev/null ||
    { echo "$dir: no 'freiburg1/2/3' in the name to pick the camera config; set CONFIG=FILE" >&2; exit 2; }
done

mkdir -p "$OUT/runs"
total=$(( ${#SEQS[@]} * $(wc -w <<< "$MODES") ))
k=0
failed=()
for dir in "${SEQS[@]}"; do
  name=$(basename "$dir"); name=${name#rgbd_dataset_}
  cfg=$(config_for "$dir")
  for mode in $MODES; do
    k=$((k + 1))
    res="$OUT/runs/$name/$mode"
    if [ -f "$res/run.json" ] && [ -z "${FORCE:-}" ]; then
      echo "== [$k/$total] $name / $mode: done before (FORCE=1 reruns it)"
      continue
    fi
    rm -rf "$res" && mkdir -p "$res"
    mode_flags "$mode"
    echo "== [$k/$total] $name / $mode"
    if ! "$BIN" run -q --deterministic -c "$cfg" -d "$dir" -o "$res" "${MODE_FLAGS[@]}" --max-frames "$FRAMES" \
        > "$res/run.log" 2>&1; then
      echo "   failed: see $res/run.log" >&2
      rm -f "$res/run.json"  # not done: the next call runs it again
      failed+=("$name/$mode")
      continue
    fi
    if [ -f "$dir/groundtruth.txt" ]; then
      "$BIN" eval --json "$dir/groundtruth.txt" "$res/trajectory.txt" > "$res/eval.json" 2> "$res/eval.err" ||
        echo "   eval failed: see $res/eval.err" >&2
    fi
    grep -E "^(ATE|time per frame)" "$res/run.log" | sed 's/^/   /' || true
  done
done
python3 "$ROOT/bench/tum_tables.py" "$OUT" > "$OUT/tables.md"
echo "tables: $OUT/tables.md"
if [ ${#failed[@]} -gt 0 ]; then
  echo "runs that failed: ${failed[*]}" >&2
  exit 1
fi
