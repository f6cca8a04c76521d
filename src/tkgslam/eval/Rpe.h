#pragma once
// Relative pose error exactly as the TUM benchmark's evaluate_rpe.py with --fixed_delta
// --delta 1 --delta_unit s: for each estimated pose i, j is the estimate closest in time to
// t_i + delta (pair dropped if j is the last pose); ground-truth poses are the nearest stamps,
// rejected if further than 2x the median ground-truth interval. The error of a pair is
// E = (P_j^-1 P_i)^-1 (Q_j^-1 Q_i), P estimate, Q ground truth.
#include <vector>

#include "tkgslam/eval/ErrorStatistics.h"
#include "tkgslam/io/TrajectoryFile.h"

namespace tkgslam::eval {

struct RpeResult {
  ErrorStatistics translation;   ///< metres (per delta, i.e. m/s for delta = 1 s)
  ErrorStatistics rotation_deg;  ///< degrees
  std::vector<double> timestamps;       ///< estimate stamp t_i of each pair
  std::vector<double> translation_errors;
  std::vector<double> rotation_errors_deg;
};

/// Throws InputError if the trajectories overlap in fewer than 2 stamps or yield no pair.
RpeResult computeRpe(const std::vector<io::TrajectoryEntry>& ground_truth,
                     const std::vector<io::TrajectoryEntry>& estimate, double delta_seconds = 1.0);

}  // namespace tkgslam::eval
