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

double rotationAngle(const Mat3& R) {
  const double c = std::clamp((R.trace() - 1.0) / 2.0, -1.0, 1.0);
  return std::acos(c);
}

}  // namespace tkgslam
