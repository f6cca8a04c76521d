# The benchmark modes as `tkgslam run` flags; sourced by bench/dynamic_benchmark.sh and
# bench/tum_benchmark.sh so both mean the same by a mode's name.
#   mode_flags MODE   -> sets the array MODE_FLAGS (non-zero status for an unknown mode)
# TK, TKG, TKGp and TKGs detect every frame, and `tkgslam run` pipelines that by default since session 61
# (the detector one frame ahead, `--pipeline`): the same trajectories as waiting for each detection,
# less time per frame. T and TG have no Kalman tracker to hold frames for, and wait. Tables of earlier
# sessions timed TK / TKG waiting.
mode_flags() {
  case "$1" in
    orb | T | TK | TG | TKG) MODE_FLAGS=(--mode "$1") ;;
    # TKGp: TKG as the paper has it, without the geometry check outside the boxes.
    TKGp) MODE_FLAGS=(--mode TKG --unboxed-check off) ;;
    # TKGa: YOLO on every 8th frame, each result used 8 frames later (tracking never waits for it),
    # OpenCV on one thread so the detector keeps to one core.
    TKGa) MODE_FLAGS=(--mode TKG --detect-every 8 --detector-latency 8 --opencv-threads 1) ;;
    # TKGl: the same, frames held back until the next detection (boxes interpolated, poses 15 frames late).
    TKGl) MODE_FLAGS=(--mode TKG --detect-every 8 --detector-latency 8 --opencv-threads 1 --lookahead) ;;
    # TKGt: lookahead with tiled runs: every 2nd frame detected, 4 frames (2x2, half size) per run,
    # one run per 8 frames as above (poses 15 frames late). `tkgslam run --fast` until session 58.
    TKGt) MODE_FLAGS=(--mode TKG --detect-every 2 --detector-tiles 4 --detector-latency 8 --opencv-threads 1 --lookahead) ;;
    # TKGf: every frame detected at 320 x 256, one frame ahead of tracking (lookahead with latency 1,
    # poses 1 frame late), OpenCV on one thread. The same as `tkgslam run --fast`.
    TKGf) MODE_FLAGS=(--mode TKG --detector-size 320 --detector-latency 1 --opencv-threads 1 --lookahead) ;;
    # TKGs: TKG with the detector's input at 320 x 256 instead of 640 x 480 (every frame detected, ~5 x faster runs).
    TKGs) MODE_FLAGS=(--mode TKG --detector-size 320) ;;
    *) return 1 ;;
  esac
}
