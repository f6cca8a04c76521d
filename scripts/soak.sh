#!/usr/bin/env bash
# Long-run memory check (issue 7): fr1_xyz looped N times (default 10) in deterministic mode;
# resident memory is logged every 100 frames (OUT/memory.tsv). Fails if memory grows by more
# than 10 % between the end of the first loop and the end of the run.
#   scripts/soak.sh [LOOPS] [OUT]      (~40 s per loop on a 2-core laptop)
set -euo pipefail
cd "$(dirname "$0")/.."
LOOPS=${1:-10}
OUT=${2:-build/soak}
SEQ="../shared/datasets/rgbd_dataset_freiburg1_xyz"
[ -d "$SEQ" ] || { echo "soak.sh: $SEQ not found" >&2; exit 2; }
build/bin/tkgslam run --deterministic --loops "$LOOPS" -c configs/tum_fr1.yaml -d "$SEQ" -o "$OUT"
# memory.tsv: frame rss_mib keyframes map_points; the first loop ends at frame 800 (792 frames).
awk -v out="$OUT" 'NR > 1 { if ($1 == 800) first = $2; last = $2; kf = $3; mp = $4 }
  END {
    if (!first) { print "soak.sh: run shorter than one loop"; exit 2 }
    printf "resident memory: %.1f MiB after loop 1, %.1f MiB at the end (%+.1f %%); %d keyframes, %d map points\n",
           first, last, 100 * (last - first) / first, kf, mp
    if (last > 1.10 * first) { print "soak.sh: memory is not flat - see " out "/memory.tsv"; exit 1 }
  }' "$OUT/memory.tsv"
