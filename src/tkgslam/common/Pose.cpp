#include "tkgslam/common/Pose.h"

#include <algorithm>
#include <cmath>

namespace tkgslam {

Pose poseFromTranslationQuaternion(const Vec3& t, double qx, double qy, double qz, double qw) {
  Eigen::Quaterniond q(qw, qx, qy, qz);
  q.normalize();
  Pose T = Pose::Identity();
  T.linear() = q.toRotationMatrix();
  T.translation() = t;
  return T;
}

Mat3 expSO3(const Vec3& omega) {
  const double theta = omega.norm();
  if (theta < 1e-12) return Mat3::Identity();
  return Eigen::AngleAxisd(theta, omega / theta).toRotationMatrix();
}

Pose orthonormalized(const Pose& T) {
  Pose out = T;
  out.linear() = Eigen::Quaterniond(T.linear()).normalized().toRotationMatrix();
  return out;
}

Pose applyIncrement(const Pose& T, const Eigen::Matrix<double, 6, 1>& delta) {
  Pose D = Pose::Identity();
  D.linear() = expSO3(delta.head<3>());
  D.translation() = delta.tail<3>();
  return orthonormalized(D * T);
}

Pose interpolatePose(const Pose& a, const Pose& b, double s) {
  const Pose A = a.inverse(), B = b.inverse();  // camera -> world
  Pose T = Pose::Identity();
  T.linear() = Eigen::Quaterniond(A.linear()).slerp(s, Eigen::Quaterniond(B.linear())).toRotationMatrix();
  T.translation() = (1 - s) * A.translation() + s * B.translation();
  return T.inverse();
}

Pose poseRoot(const Pose& T, int n) {
  if (n <= 1) return T;
  const Eigen::AngleAxisd aa(T.linear());
  Pose S = Pose::Identity();
  S.linear() = Eigen::AngleAxisd(aa.angle() / n, aa.axis()).toRotationMatrix();
  // n steps translate by (I + R + ... + R^(n-1)) t; invert that sum (well conditioned for angles < pi).
  Mat3 sum = Mat3::Zero(), Rk = Mat3::Identity();
  for (int k = 0; k < n; ++k) {
    sum += Rk;
    Rk = S.linear() * Rk;
  }
  S.translation() = sum.partialPivLu().solve(T.translation());
  return S;
}

double rotationAngle(const Mat3& R) {
  const double c = std::clamp((R.trace() - 1.0) / 2.0, -1.0, 1.0);
  return std::acos(c);
}

// Not rotationAngle(): its acos (kept TUM-exact for RPE) has a floor of ~1e-8 rad near zero, where
// these gaps mostly are; the angle-axis form is accurate there.
PoseGap poseGap(const Pose& a_cw, const Pose& b_cw) {
  return {(a_cw.inverse().translation() - b_cw.inverse().translation()).norm(),
          180.0 / M_PI * Eigen::AngleAxisd(a_cw.linear() * b_cw.linear().transpose()).angle()};
}

}  // namespace tkgslam
