#include "tkgslam/eval/Ate.h"

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

AteResult computeAte(const std::vector<io::TrajectoryEntry>& ground_truth,
                     const std::vector<io::TrajectoryEntry>& estimate, double max_time_difference) {
  const auto pairs = associateTimestamps(stampsOf(ground_truth), stampsOf(estimate), max_time_difference);
  if (pairs.size() < 2) {
    throw InputError(
        fmt::format("fewer than 2 timestamps of the estimate match the ground truth (|dt| < {:g} s); "
                    "are these the right files?",
                    max_time_difference));
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
