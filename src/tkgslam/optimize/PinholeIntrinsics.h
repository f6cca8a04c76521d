#pragma once
// The camera model the optimisers use: a pinhole with a virtual stereo camera from the depth
// (RGB-D as in ORB-SLAM2), its projection and that projection's Jacobian.
#include "tkgslam/common/Pose.h"

namespace tkgslam::optimize {

struct PinholeIntrinsics {
  double fx, fy, cx, cy;
  double bf;  ///< virtual stereo baseline * fx
};

/// The intrinsics the optimisers use, from the camera and the depth's virtual baseline.
inline PinholeIntrinsics intrinsicsOf(double fx, double fy, double cx, double cy, double baseline_fx) {
  return {fx, fy, cx, cy, baseline_fx};
}

/// (u, v, u_right) in pixels of a point p_c in camera coordinates (metres, z > 0); u_right = u - bf / z.
inline Vec3 projectStereo(const PinholeIntrinsics& K, const Vec3& p_c) {
  const double iz = 1.0 / p_c.z();
  const double u = K.fx * p_c.x() * iz + K.cx;
  return {u, K.fy * p_c.y() * iz + K.cy, u - K.bf * iz};
}

/// d (u, v, u_right) / d p_c; with `stereo` false the u_right row is 0 (an observation without depth).
inline Mat3 projectStereoJacobian(const PinholeIntrinsics& K, const Vec3& p_c, bool stereo) {
  const double iz = 1.0 / p_c.z(), iz2 = iz * iz;
  Mat3 J;
  J << K.fx * iz, 0, -K.fx * p_c.x() * iz2,  //
      0, K.fy * iz, -K.fy * p_c.y() * iz2,   //
      0, 0, 0;
  if (stereo) J.row(2) << K.fx * iz, 0, -K.fx * p_c.x() * iz2 + K.bf * iz2;
  return J;
}

/// The bundle adjustment's residual of an observation (uv, u_right in pixels; u_right < 0: no depth,
/// third row 0) of the camera point p_c: s * (observed - predicted), s = sqrt(information).
inline Vec3 stereoResidual(const PinholeIntrinsics& K, const Vec2& uv, double u_right, double s, const Vec3& p_c) {
  const Vec3 predicted = projectStereo(K, p_c);
  return {s * (uv.x() - predicted[0]), s * (uv.y() - predicted[1]), u_right >= 0 ? s * (u_right - predicted[2]) : 0.0};
}

}  // namespace tkgslam::optimize
