#include <gtest/gtest.h>

#include "tkgslam/common/Pose.h"
#include "tkgslam/io/TrajectoryFile.h"

namespace tkgslam {
namespace {

TEST(Pose, QuaternionConventionIsXyzwAndHamilton) {
  // 90 degrees about z: (x, y, z, w) = (0, 0, sin 45, cos 45) maps the x axis onto the y axis.
  const double s = std::sqrt(0.5);
  const Pose T = poseFromTranslationQuaternion(Vec3(1, 2, 3), 0, 0, s, s);
  EXPECT_TRUE((T.linear() * Vec3::UnitX()).isApprox(Vec3::UnitY(), 1e-12));
  EXPECT_TRUE((T * Vec3::Zero()).isApprox(Vec3(1, 2, 3)));
  // Unnormalised input is normalised.
  const Pose T2 = poseFromTranslationQuaternion(Vec3::Zero(), 0, 0, 2 * s, 2 * s);
  EXPECT_TRUE(T2.linear().isApprox(T.linear(), 1e-12));
}

TEST(Pose, CompositionFollowsTheFrameNamingConvention) {
  // T_ab * T_bc = T_ac: a point in c goes to b then to a.
  Pose T_ab = Pose::Identity(), T_bc = Pose::Identity();
  T_ab.linear() = Eigen::AngleAxisd(0.4, Vec3::UnitY()).toRotationMatrix();
  T_ab.translation() = Vec3(0.5, 0, 0);
  T_bc.linear() = Eigen::AngleAxisd(-1.1, Vec3::UnitX()).toRotationMatrix();
  T_bc.translation() = Vec3(0, 0.2, 1);
  const Vec3 p_c(0.3, -0.7, 2.0);
  EXPECT_TRUE(((T_ab * T_bc) * p_c).isApprox(T_ab * (T_bc * p_c), 1e-12));
  // The camera centre is the translation of T_wc = T_cw^-1.
  const Pose T_cw = T_ab;
  EXPECT_TRUE((T_cw * T_cw.inverse().translation()).isZero(1e-12));
}

TEST(Pose, IncrementIsALeftPerturbationAndStaysOrthonormal) {
  Pose T = Pose::Identity();
  T.translation() = Vec3(1, 0, 0);
  Eigen::Matrix<double, 6, 1> d;
  d << 0, 0, M_PI / 2, 0, 0, 0.5;
  const Pose U = applyIncrement(T, d);
  EXPECT_TRUE(U.translation().isApprox(Vec3(0, 1, 0.5), 1e-12));
  Pose drift = T;
  drift.linear() *= 1.001;  // not a rotation any more
  EXPECT_NEAR(orthonormalized(drift).linear().determinant(), 1.0, 1e-12);
  EXPECT_NEAR(rotationAngle(U.linear()), M_PI / 2, 1e-12);
}

TEST(Pose, RootIsTheConstantStepThatComposesToThePose) {
  Pose S = Pose::Identity();
  S.linear() = Eigen::AngleAxisd(0.05, Vec3(1, 2, -1).normalized()).toRotationMatrix();
  S.translation() = Vec3(0.01, -0.02, 0.004);
  for (int n : {1, 2, 4, 10}) {
    Pose T = Pose::Identity();
    for (int k = 0; k < n; ++k) T = S * T;
    const Pose R = poseRoot(T, n);
    EXPECT_TRUE(R.linear().isApprox(S.linear(), 1e-10)) << n;
    EXPECT_TRUE(R.translation().isApprox(S.translation(), 1e-10)) << n;
  }
  // No rotation: the translation splits evenly.
  Pose T = Pose::Identity();
  T.translation() = Vec3(0.3, 0, -0.6);
  EXPECT_TRUE(poseRoot(T, 3).translation().isApprox(Vec3(0.1, 0, -0.2), 1e-12));
  EXPECT_TRUE(poseRoot(T, 3).linear().isIdentity(1e-12));
}

TEST(Pose, InterpolationMovesTheCameraCentreStraightAndTurnsAtAConstantRate) {
  const Pose a = poseFromTranslationQuaternion(Vec3(0.3, -0.2, 1.0), 0.1, 0.2, -0.1, 0.97);
  Pose step = Pose::Identity();
  step.linear() = Eigen::AngleAxisd(0.09, Vec3(0.2, 1.0, -0.3).normalized()).toRotationMatrix();
  step.translation() = Vec3(0.02, -0.01, 0.015);
  Pose b = a;
  for (int k = 0; k < 3; ++k) b = step * b;  // three frames of a turning, moving camera
  EXPECT_TRUE(interpolatePose(a, b, 0).isApprox(a, 1e-12));
  EXPECT_TRUE(interpolatePose(a, b, 1).isApprox(b, 1e-12));
  const Pose m = interpolatePose(a, b, 1.0 / 3);
  // A third of the rotation between them, and a centre a third of the way along the chord.
  EXPECT_NEAR(rotationAngle((m.linear() * a.linear().transpose())), 0.09, 1e-9);
  const Vec3 ca = a.inverse().translation(), cb = b.inverse().translation();
  EXPECT_LT((m.inverse().translation() - (ca + (cb - ca) / 3)).norm(), 1e-12);
}

TEST(Pose, GapIsTheCameraCentresDistanceAndTheRelativeRotation) {
  const Pose a = poseFromTranslationQuaternion(Vec3(0.3, -0.2, 1.0), 0.1, 0.2, -0.1, 0.97);
  Pose turn = Pose::Identity();  // 5 deg about an axis through the camera centre: the centre stays
  turn.linear() = Eigen::AngleAxisd(5.0 * M_PI / 180, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  const Pose b = turn * a;
  EXPECT_NEAR(poseGap(a, b).deg, 5.0, 1e-9);
  EXPECT_NEAR(poseGap(a, b).metres, 0.0, 1e-12);
  Pose shift = Pose::Identity();  // the camera moved 4 cm along its own x axis: T_cw gains -0.04 x
  shift.translation() = Vec3(-0.04, 0, 0);
  EXPECT_NEAR(poseGap(shift * a, a).metres, 0.04, 1e-12);
  EXPECT_NEAR(poseGap(shift * a, a).deg, 0.0, 1e-9);
}

TEST(Pose, TrajectoryEntryPoseIsCameraToWorld) {
  io::TrajectoryEntry e;
  e.t = Vec3(1, 2, 3);
  e.q_xyzw = Eigen::Vector4d(0, 0, 0, 1);
  EXPECT_TRUE((e.pose() * Vec3::Zero()).isApprox(Vec3(1, 2, 3)));  // camera origin in world
}

}  // namespace
}  // namespace tkgslam
