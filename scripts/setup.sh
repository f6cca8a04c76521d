#!/usr/bin/env bash
# One command on a fresh Debian 12 machine: install the Debian packages, build (Release), and run
# SLAM on the bundled example sequence (../shared/datasets/rgbd_dataset_freiburg1_xyz).
set -euo pipefail
cd "$(dirname "$0")/.."
./scripts/deps.sh
./scripts/build.sh
SEQ="../shared/datasets/rgbd_dataset_freiburg1_xyz"
if [ ! -d "$SEQ" ]; then
  echo "Built. The example sequence $SEQ is not here; see README for running on your own data."
  exit 0
fi
OUT="out/fr1_xyz"
./build/bin/tkgslam run --config configs/tum_fr1.yaml --dataset "$SEQ" --out "$OUT" --report
./build/bin/tkgslam eval "$SEQ/groundtruth.txt" "$OUT/trajectory.txt" --frames "$SEQ" --plot "$OUT/trajectory.svg"
echo "Outputs in $OUT: report.html trajectory.txt keyframes.txt map.ply timing.json trajectory.svg"
