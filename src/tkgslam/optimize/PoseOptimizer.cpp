#include "tkgslam/optimize/PoseOptimizer.h"

#include <cmath>

#include <Eigen/Cholesky>

namespace tkgslam::optimize {

namespace {

using Vec6 = Eigen::Matrix<double, 6, 1>;
using Mat6 = Eigen::Matrix<double, 6, 6>;

// Residual (observed - predicted) and its Jacobian w.r.t. a left SE(3) increment [rot; trans].
// Returns false if the point is behind the camera.
bool residual(const PoseObservation& o, const PinholeIntrinsics& K, const Pose& T, Eigen::Vector3d& e,
              Eigen::Matrix<double, 3, 6>& J, bool stereo) {
  const Vec3 pc = T * o.p_w;
  if (pc.z() <= 1e-6) return false;
  const Vec3 predicted = projectStereo(K, pc);
  e[0] = o.uv.x() - predicted[0];
  e[1] = o.uv.y() - predicted[1];
  e[2] = stereo ? o.u_right - predicted[2] : 0.0;
  Eigen::Matrix<double, 3, 6> Jt;  // d(pc)/d(increment): [-[pc]x, I]
  Jt << -skew(pc), Mat3::Identity();
  J = -projectStereoJacobian(K, pc, stereo) * Jt;  // residual = observed - predicted
  if (!stereo) J.row(2).setZero();  // -0 from the product
  return true;
}

}  // namespace

int optimizePose(const std::vector<PoseObservation>& obs, const PinholeIntrinsics& K, Pose& T_cw,
                 std::vector<char>& outlier, const PoseOptimizerOptions& opt) {
  const size_t n = obs.size();
  outlier.assign(n, 0);
  if (n == 0) return 0;
  Eigen::Vector3d e;
  Eigen::Matrix<double, 3, 6> J;
  int inliers = 0;
  for (int round = 0; round < opt.rounds; ++round) {
    const bool robust = round < 2;
    int used = 0;
    for (int it = 0; it < opt.iterations; ++it) {
      Mat6 H = Mat6::Zero();
      Vec6 b = Vec6::Zero();
      used = 0;
      for (size_t i = 0; i < n; ++i) {
        if (outlier[i]) continue;
        const bool stereo = obs[i].u_right >= 0;
        if (!residual(obs[i], K, T_cw, e, J, stereo)) continue;
        const double chi2 = e.squaredNorm() * obs[i].information;
        double w = obs[i].information;
        if (robust) {
          const double delta = std::sqrt(stereo ? opt.chi2_stereo : opt.chi2_mono);
          const double r = std::sqrt(chi2);
          if (r > delta) w *= delta / r;
        }
        H.noalias() += w * J.transpose() * J;
        b.noalias() -= w * J.transpose() * e;
        ++used;
      }
      if (used < 3) break;
      H.diagonal().array() += 1e-9;  // guards against a rank-deficient system
      const Vec6 delta = H.ldlt().solve(b);
      if (!delta.allFinite()) break;
      T_cw = applyIncrement(T_cw, delta);
      if (delta.squaredNorm() < 1e-12) break;
    }
    // Re-classify every observation with the current pose.
    inliers = 0;
    for (size_t i = 0; i < n; ++i) {
      const bool stereo = obs[i].u_right >= 0;
      if (!residual(obs[i], K, T_cw, e, J, stereo)) {
        outlier[i] = 1;
        continue;
      }
      const double chi2 = e.squaredNorm() * obs[i].information;
      outlier[i] = chi2 > (stereo ? opt.chi2_stereo : opt.chi2_mono);
      inliers += !outlier[i];
    }
    if (used < 10) break;
  }
  return inliers;
}

}  // namespace tkgslam::optimize
