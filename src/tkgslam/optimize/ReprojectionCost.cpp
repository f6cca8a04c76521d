#include "tkgslam/optimize/ReprojectionCost.h"

#include <cmath>

namespace tkgslam::optimize {

namespace {
using RowMat3 = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>;
}  // namespace

ReprojectionCost::ReprojectionCost(const BundleObservation& o, const PinholeIntrinsics& K)
    : uv_(o.uv), u_right_(o.u_right), K_(K), s_(std::sqrt(o.information)) {}

void ReprojectionCost::residualAt(const Vec3& pc, double* r) const {
  Eigen::Map<Vec3> residual(r);
  residual = stereoResidual(K_, uv_, u_right_, s_, pc);
}

bool ReprojectionCost::Evaluate(double const* const* parameters, double* residuals, double** jacobians) const {
  const double* q = parameters[0];
  const Eigen::Map<const Vec3> pw(parameters[2]);
  const Vec3 pc = Eigen::Map<const Eigen::Quaterniond>(q) * pw + Eigen::Map<const Vec3>(parameters[1]);
  residualAt(pc, residuals);
  if (!jacobians) return true;

  // Eigen rotates p by q (not normalised) as p + 2w (v x p) + 2 v x (v x p), v = (x, y, z): a
  // polynomial in q, differentiated as such (what automatic differentiation does).
  const Vec3 v(q[0], q[1], q[2]);
  const double w = q[3];
  // d residual / d camera point.
  const Mat3 A = -s_ * projectStereoJacobian(K_, pc, u_right_ >= 0);

  if (jacobians[0]) {
    Eigen::Matrix<double, 3, 4> dR_dq;
    const double vp = v.dot(pw);
    dR_dq.leftCols<3>() = -2.0 * w * skew(pw) + 2.0 * (vp * Mat3::Identity() + v * pw.transpose() - 2.0 * pw * v.transpose());
    dR_dq.col(3) = 2.0 * v.cross(pw);
    Eigen::Map<Eigen::Matrix<double, 3, 4, Eigen::RowMajor>> J(jacobians[0]);
    J = A * dR_dq;
  }
  if (jacobians[1]) {
    Eigen::Map<RowMat3> J(jacobians[1]);
    J = A;
  }
  if (jacobians[2]) {
    const Mat3 V = skew(v);
    Eigen::Map<RowMat3> J(jacobians[2]);
    J = A * (Mat3::Identity() + 2.0 * w * V + 2.0 * V * V);
  }
  return true;
}

}  // namespace tkgslam::optimize
