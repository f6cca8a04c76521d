#pragma once
// Rigid-body poses. Naming convention: T_ab maps points expressed in frame b into frame a,
// so T_cw maps world to camera and T_wc = T_cw^-1 is the camera pose in the world.
// Translations are in metres.
#include <Eigen/Core>
#include <Eigen/Geometry>

namespace tkgslam {

using Pose = Eigen::Isometry3d;
using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;

/// A timestamped camera pose as stored in TUM trajectory files (camera-to-world, T_wc).
struct StampedPose {
  double timestamp = 0.0;  ///< seconds
  Pose T_wc = Pose::Identity();
};

/// Build a pose from a translation and a (not necessarily normalised) quaternion (x, y, z, w).
Pose poseFromTranslationQuaternion(const Vec3& t, double qx, double qy, double qz, double qw);

/// The cross-product matrix: skew(a) * b = a x b.
inline Mat3 skew(const Vec3& a) {
  Mat3 m;
  m << 0, -a.z(), a.y(), a.z(), 0, -a.x(), -a.y(), a.x(), 0;
  return m;
}

/// SO(3) exponential map (rotation vector in radians -> rotation matrix).
Mat3 expSO3(const Vec3& omega);

/// Projects the rotation part back onto SO(3). Products of poses accumulate rounding error that
/// the constant-velocity model would otherwise amplify frame after frame.
Pose orthonormalized(const Pose& T);

/// SE(3) increment: left-multiplies a pose by exp of a 6-vector [rotation (rad); translation (m)].
Pose applyIncrement(const Pose& T, const Eigen::Matrix<double, 6, 1>& delta);

/// The constant step S with S^n = T (n >= 1): rotation by 1/n of T's angle about T's axis, and the
/// translation that n such steps add up to T's. E.g. the per-frame velocity over an n-frame gap.
Pose poseRoot(const Pose& T, int n);

/// The camera pose a share `s` (0 = a, 1 = b) of the way from world->camera pose `a` to `b`: the
/// camera centre moves on the straight line, the orientation by slerp (constant angular rate).
Pose interpolatePose(const Pose& a, const Pose& b, double s);

/// Rotation angle of a rotation matrix in radians, in [0, pi].
double rotationAngle(const Mat3& R);

/// How far apart two world->camera poses are: distance of the camera centres (metres) and angle of
/// the relative rotation (degrees).
struct PoseGap {
  double metres;
  double deg;
};
PoseGap poseGap(const Pose& a_cw, const Pose& b_cw);

}  // namespace tkgslam
