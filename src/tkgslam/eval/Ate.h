#pragma once
// Absolute trajectory error exactly as the TUM benchmark's evaluate_ate.py: associate estimate
// and ground truth stamps (|dt| < 0.02 s by default), rigidly align the estimated positions to the ground
// truth (SVD / Horn, no scale), and report statistics of the position residuals in metres.
#include <vector>

#include "tkgslam/common/Pose.h"
#include "tkgslam/eval/ErrorStatistics.h"
#include "tkgslam/io/TrajectoryFile.h"

namespace tkgslam::eval {

struct AteResult {
  ErrorStatistics stats;        ///< position error statistics, metres
  Pose T_gt_est = Pose::Identity();  ///< alignment applied to the estimate
  std::vector<double> timestamps;    ///< ground-truth stamps of the matched pairs
  std::vector<Vec3> gt_positions;    ///< matched ground-truth positions
  std::vector<Vec3> est_aligned;     ///< matched estimated positions after alignment
  std::vector<double> errors;        ///< per-pair error, metres
};

/// Throws InputError when fewer than 2 pairs can be associated.
AteResult computeAte(const std::vector<io::TrajectoryEntry>& ground_truth,
                     const std::vector<io::TrajectoryEntry>& estimate,
                     double max_time_difference = 0.02);

/// Least-squares rigid transform (rotation + translation, no scale) mapping `model` onto `data`.
Pose alignRigid(const std::vector<Vec3>& model, const std::vector<Vec3>& data);

}  // namespace tkgslam::eval
