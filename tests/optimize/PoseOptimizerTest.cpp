#include <random>

#include <gtest/gtest.h>

#include "tkgslam/optimize/PoseOptimizer.h"

namespace tkgslam {
namespace {

// Synthetic RGB-D observations of random points seen by a camera at a known pose; 30 % of them
// are replaced by gross outliers. The optimiser must recover the pose from a perturbed start
// and flag the outliers.
TEST(PoseOptimizer, RecoversKnownPoseWithThirtyPercentOutliers) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> ux(-1.5, 1.5), uz(1.0, 4.0), upix(0, 640);
  std::normal_distribution<double> noise(0.0, 0.5);
  const optimize::PinholeIntrinsics K{517.3, 516.5, 318.6, 255.3, 40.0};
  Pose T_true = Pose::Identity();
  T_true.linear() = Eigen::AngleAxisd(0.3, Vec3(0.2, 1, 0.1).normalized()).toRotationMatrix();
  T_true.translation() = Vec3(0.1, -0.05, 0.2);

  std::vector<optimize::PoseObservation> obs;
  std::vector<char> is_outlier;
  for (int i = 0; i < 300; ++i) {
    const Vec3 pc(ux(rng), ux(rng) * 0.7, uz(rng));
    optimize::PoseObservation o;
    o.p_w = T_true.inverse() * pc;
    o.uv = Vec2(K.fx * pc.x() / pc.z() + K.cx + noise(rng), K.fy * pc.y() / pc.z() + K.cy + noise(rng));
    o.u_right = (i % 3 == 0) ? -1.0 : o.uv.x() - K.bf / pc.z();  // a third without depth
    const bool outlier = i % 10 < 3;
    if (outlier) {
      o.uv = Vec2(upix(rng), upix(rng) * 0.75);
      if (o.u_right >= 0) o.u_right = o.uv.x() - 20;
    }
    obs.push_back(o);
    is_outlier.push_back(outlier);
  }
  Pose T = Pose::Identity();  // ~17 degrees and 23 cm away from the truth
  std::vector<char> flagged;
  const int inliers = optimize::optimizePose(obs, K, T, flagged);

  EXPECT_LT((T.translation() - T_true.translation()).norm(), 0.005);
  EXPECT_LT(rotationAngle(T.linear() * T_true.linear().transpose()), 0.2 * M_PI / 180);
  int correct = 0;
  for (size_t i = 0; i < obs.size(); ++i) correct += flagged[i] == is_outlier[i];
  EXPECT_GE(correct, 290);
  EXPECT_GE(inliers, 200);
  EXPECT_LE(inliers, 215);
}

TEST(PoseOptimizer, NoObservationsLeavesPoseUnchanged) {
  Pose T = Pose::Identity();
  T.translation() = Vec3(1, 2, 3);
  std::vector<char> flagged;
  EXPECT_EQ(optimize::optimizePose({}, {500, 500, 320, 240, 40}, T, flagged), 0);
  EXPECT_TRUE(T.translation().isApprox(Vec3(1, 2, 3)));
}

}  // namespace
}  // namespace tkgslam
