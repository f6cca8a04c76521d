#include "tkgslam/eval/Rpe.h"

#include <algorithm>
#include <cmath>
#include <numeric>

#include <fmt/format.h>

#include "tkgslam/common/Error.h"
#include "tkgslam/eval/Association.h"

namespace tkgslam::eval {

namespace {
struct Track {
  std::vector<double> stamps;
  std::vector<Pose> poses;
};

// The RPE script drops poses whose quaternion is all zero.
Track toTrack(const std::vector<io::TrajectoryEntry>& traj) {
  Track t;
  for (const auto& e : traj) {
    if (e.hasZeroQuaternion()) continue;
    t.stamps.push_back(e.timestamp);
    t.poses.push_back(e.pose());
  }
  return t;
}

/// Where each estimated pose is in the delta's unit (evaluate_rpe.py's index_est): its time, its
/// number, or the distance / rotation travelled along the estimate up to it.
std::vector<double> indexAlong(const Track& est, DeltaUnit unit) {
  if (unit == DeltaUnit::Seconds) return est.stamps;
  std::vector<double> index(est.stamps.size(), 0.0);
  if (unit == DeltaUnit::Frames) {
    std::iota(index.begin(), index.end(), 0.0);
    return index;
  }
  for (size_t k = 1; k < index.size(); ++k) {
    const Pose step = est.poses[k - 1].inverse() * est.poses[k];
    const double travelled = unit == DeltaUnit::Metres ? step.translation().norm() : rotationAngle(step.linear());
    index[k] = index[k - 1] + (unit == DeltaUnit::Degrees ? travelled * 180.0 / M_PI : travelled);
  }
  return index;
}
}  // namespace

const char* toString(DeltaUnit unit) {
  switch (unit) {
    case DeltaUnit::Seconds: return "s";
    case DeltaUnit::Frames: return "f";
    case DeltaUnit::Metres: return "m";
    case DeltaUnit::Radians: return "rad";
    case DeltaUnit::Degrees: return "deg";
  }
  return "?";
}

DeltaUnit parseDeltaUnit(const std::string& name) {
  for (const auto unit : kDeltaUnits) {
    if (name == toString(unit)) return unit;
  }
  throw InputError(fmt::format("unknown RPE delta unit '{}' (s, f, m, rad or deg)", name));
}

RpeResult computeRpe(const std::vector<io::TrajectoryEntry>& ground_truth,
                     const std::vector<io::TrajectoryEntry>& estimate, double delta_seconds) {
  return computeRpe(ground_truth, estimate, RpeOptions{delta_seconds, DeltaUnit::Seconds, 1.0});
}

RpeResult computeRpe(const std::vector<io::TrajectoryEntry>& ground_truth,
                     const std::vector<io::TrajectoryEntry>& estimate, const RpeOptions& options) {
  const Track gt = toTrack(ground_truth), est = toTrack(estimate);
  if (gt.stamps.size() < 2 || est.stamps.size() < 2) {
    throw InputError("RPE needs at least 2 valid poses in both the ground truth and the estimate");
  }
  // Overlap check as in the script: distinct estimate stamps reachable through the ground truth.
  std::vector<int> overlap;
  for (double t : est.stamps) {
    const double t_gt = gt.stamps[findClosestIndex(gt.stamps, t)];
    const int k = findClosestIndex(est.stamps, t_gt);
    if (std::find(overlap.begin(), overlap.end(), k) == overlap.end()) overlap.push_back(k);
    if (overlap.size() >= 2) break;
  }
  if (overlap.size() < 2) {
    throw InputError("the estimate and ground truth overlap in fewer than 2 timestamps");
  }

  std::vector<double> intervals;
  for (size_t k = 1; k < gt.stamps.size(); ++k) intervals.push_back(gt.stamps[k] - gt.stamps[k - 1]);
  std::vector<double> sorted = intervals;
  std::sort(sorted.begin(), sorted.end());
  const size_t m = sorted.size() / 2;
  const double median_interval = sorted.size() % 2 ? sorted[m] : 0.5 * (sorted[m - 1] + sorted[m]);
  const double max_gt_difference = 2.0 * median_interval;

  RpeResult r;
  const std::vector<double> index = indexAlong(est, options.unit);
  const int n = static_cast<int>(est.stamps.size());
  for (int i = 0; i < n; ++i) {
    const int j = findClosestIndex(index, index[i] + options.delta);
    if (j == n - 1) continue;
    const int gi = findClosestIndex(gt.stamps, est.stamps[i]);
    const int gj = findClosestIndex(gt.stamps, est.stamps[j]);
    if (std::abs(gt.stamps[gi] - est.stamps[i]) > max_gt_difference ||
        std::abs(gt.stamps[gj] - est.stamps[j]) > max_gt_difference) {
      continue;
    }
    Pose rel_est = est.poses[j].inverse() * est.poses[i];
    rel_est.translation() *= options.scale;
    const Pose rel_gt = gt.poses[gj].inverse() * gt.poses[gi];
    const Pose E = rel_est.inverse() * rel_gt;
    r.timestamps.push_back(est.stamps[i]);
    r.translation_errors.push_back(E.translation().norm());
    r.rotation_errors_deg.push_back(rotationAngle(E.linear()) * 180.0 / M_PI);
  }
  if (r.timestamps.empty()) {
    const char* unit = toString(options.unit);
    throw InputError(fmt::format("RPE: no pose pair {:g} {} apart matches the ground truth (the estimate spans {:.2f} {})",
                                 options.delta, unit, index.back() - index.front(), unit));
  }
  r.translation = ErrorStatistics::compute(r.translation_errors);
  r.rotation_deg = ErrorStatistics::compute(r.rotation_errors_deg);
  return r;
}

}  // namespace tkgslam::eval
