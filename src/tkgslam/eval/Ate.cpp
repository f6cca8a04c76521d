#include "tkgslam/eval/Ate.h"

#include <cmath>
#include <string>
#include <utility>

#include <Eigen/SVD>
#include <fmt/format.h>

#include "tkgslam/common/Error.h"
#include "tkgslam/eval/Association.h"

namespace tkgslam::eval {

namespace {
std::vector<double> stampsOf(const std::vector<io::TrajectoryEntry>& traj) {
  std::vector<double> s;
  s.reserve(traj.size());
  for (const auto& e : traj) s.push_back(e.timestamp);
  return s;
}
}  // namespace

Pose alignRigid(const std::vector<Vec3>& model, const std::vector<Vec3>& data) {
  Vec3 mu_m = Vec3::Zero(), mu_d = Vec3::Zero();
  for (size_t i = 0; i < model.size(); ++i) {
    mu_m += model[i];
    mu_d += data[i];
  }
  mu_m /= double(model.size());
  mu_d /= double(data.size());
  Mat3 W = Mat3::Zero();  // sum of (model_i - mu_m)(data_i - mu_d)^T
  for (size_t i = 0; i < model.size(); ++i) W += (model[i] - mu_m) * (data[i] - mu_d).transpose();
  // R maximises trace(R W): R = V S U^T with W = U D V^T, S fixing reflections.
  Eigen::JacobiSVD<Mat3> svd(W, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Mat3 S = Mat3::Identity();
  if (svd.matrixU().determinant() * svd.matrixV().determinant() < 0) S(2, 2) = -1;
  Pose T = Pose::Identity();
  T.linear() = svd.matrixV() * S * svd.matrixU().transpose();
  T.translation() = mu_d - T.linear() * mu_m;
  return T;
}

namespace {

/// Why no timestamps pair up, when the stamps say: another unit, or no overlap in time.
std::string whyNoPairs(const std::vector<io::TrajectoryEntry>& gt, const std::vector<io::TrajectoryEntry>& est) {
  if (gt.size() < 2 || est.size() < 2) {
    return fmt::format(": the {} has {} pose(s)", gt.size() < 2 ? "ground truth" : "estimate",
                       gt.size() < 2 ? gt.size() : est.size());
  }
  const double g0 = gt.front().timestamp, g1 = gt.back().timestamp;
  const double e0 = est.front().timestamp, e1 = est.back().timestamp;
  for (const auto& [factor, unit] : {std::pair{1e9, "nanoseconds"}, {1e6, "microseconds"}, {1e3, "milliseconds"}}) {
    if (g0 > 0 && std::abs(e0 / (g0 * factor) - 1) < 0.01) {
      return fmt::format(": the estimate's timestamps are {:g} times the ground truth's - {}? (TUM's are seconds)",
                         factor, unit);
    }
    if (e0 > 0 && std::abs(g0 / (e0 * factor) - 1) < 0.01) {
      return fmt::format(": the ground truth's timestamps are {:g} times the estimate's - {}? (TUM's are seconds)",
                         factor, unit);
    }
  }
  if (e1 < g0 || e0 > g1) {
    return fmt::format(": the estimate spans {:.3f}-{:.3f} s and the ground truth {:.3f}-{:.3f} s, which do not "
                       "overlap (eval --offset shifts the estimate)",
                       e0, e1, g0, g1);
  }
  return "; are these the right files?";
}

}  // namespace

AteResult computeAte(const std::vector<io::TrajectoryEntry>& ground_truth,
                     const std::vector<io::TrajectoryEntry>& estimate, double max_time_difference) {
  const auto pairs = associateTimestamps(stampsOf(ground_truth), stampsOf(estimate), max_time_difference);
  if (pairs.size() < 2) {
    throw InputError(fmt::format("fewer than 2 timestamps of the estimate match the ground truth (|dt| < {:g} s){}",
                                 max_time_difference, whyNoPairs(ground_truth, estimate)));
  }
  AteResult r;
  std::vector<Vec3> est;
  for (const auto& [i, j] : pairs) {
    r.timestamps.push_back(ground_truth[i].timestamp);
    r.gt_positions.push_back(ground_truth[i].t);
    est.push_back(estimate[j].t);
  }
  r.T_gt_est = alignRigid(est, r.gt_positions);
  for (size_t k = 0; k < est.size(); ++k) {
    r.est_aligned.push_back(r.T_gt_est * est[k]);
    r.errors.push_back((r.est_aligned.back() - r.gt_positions[k]).norm());
  }
  r.stats = ErrorStatistics::compute(r.errors);
  return r;
}

}  // namespace tkgslam::eval
