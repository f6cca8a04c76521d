#pragma once
// Relative pose error exactly as the TUM benchmark's evaluate_rpe.py with --fixed_delta (by
// default --delta 1 --delta_unit s): for each estimated pose i, j is the estimate closest to
// i + delta in the unit's index - time, frame number, distance or rotation travelled along the
// estimate (pair dropped if j is the last pose); ground-truth poses are the nearest stamps,
// rejected if further than 2x the median ground-truth interval. The error of a pair is
// E = (s(P_j^-1 P_i))^-1 (Q_j^-1 Q_i), P estimate, Q ground truth, s the estimate's scale on the
// relative translation.
#include <string>
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

/// evaluate_rpe.py's --delta_unit: what the delta between the two poses of a pair counts.
enum class DeltaUnit { Seconds, Frames, Metres, Radians, Degrees };
inline constexpr DeltaUnit kDeltaUnits[] = {DeltaUnit::Seconds, DeltaUnit::Frames, DeltaUnit::Metres,
                                            DeltaUnit::Radians, DeltaUnit::Degrees};

/// The unit's name in evaluate_rpe.py (s, f, m, rad, deg).
const char* toString(DeltaUnit unit);
/// Parses s, f, m, rad or deg; throws InputError otherwise.
DeltaUnit parseDeltaUnit(const std::string& name);

struct RpeOptions {
  double delta = 1.0;
  DeltaUnit unit = DeltaUnit::Seconds;
  double scale = 1.0;  ///< on the estimate's relative translations (evaluate_rpe.py's --scale)
};

/// Throws InputError if the trajectories overlap in fewer than 2 stamps or yield no pair.
RpeResult computeRpe(const std::vector<io::TrajectoryEntry>& ground_truth,
                     const std::vector<io::TrajectoryEntry>& estimate, const RpeOptions& options);
/// The TUM default: pairs `delta_seconds` apart.
RpeResult computeRpe(const std::vector<io::TrajectoryEntry>& ground_truth,
                     const std::vector<io::TrajectoryEntry>& estimate, double delta_seconds = 1.0);

}  // namespace tkgslam::eval
