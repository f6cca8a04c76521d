#pragma once
// The one-file HTML report of a run (no network access needed to view it): trajectory vs ground
// truth (top and side views, ATE error coloured), error and RPE over time, timings, counts, the
// config, a 3-D view of the map / keyframes / trajectory (canvas, orbit and zoom with the mouse),
// and for dynamic runs the ratio T, boxes (detected vs Kalman-filled), dropped keypoints and
// thumbnails with the boxes drawn.
#include <string>

namespace tkgslam::report {

/// Builds OUTDIR/report.html from the files `tkgslam run` wrote into OUTDIR (trajectory.txt,
/// keyframes.txt, map.ply, timing.json, run.json, config_used.yaml, dynamic.jsonl). Returns the
/// path. Throws InputError if OUTDIR is not a run's output folder.
std::string writeHtmlReport(const std::string& out_dir);

}  // namespace tkgslam::report
