#include <gtest/gtest.h>

#include "tkgslam/common/Error.h"
#include "tkgslam/eval/Association.h"
#include "tkgslam/eval/Ate.h"
#include "tkgslam/eval/Rpe.h"

namespace tkgslam {
namespace {

io::TrajectoryEntry entry(double t, Vec3 p, Eigen::Quaterniond q = Eigen::Quaterniond::Identity()) {
  io::TrajectoryEntry e;
  e.timestamp = t;
  e.t = p;
  e.q_xyzw = Eigen::Vector4d(q.x(), q.y(), q.z(), q.w());
  return e;
}

TEST(Association, StrictWindowGreedyBySmallestDifference) {
  // 1.00 is 0.015 from 1.015 and 0.005 from 0.995: greedy takes the closer pair first.
  const std::vector<double> a{1.0, 2.0, 3.0};
  const std::vector<double> b{0.995, 1.015, 2.03, 3.019};
  const auto m = eval::associateTimestamps(a, b, 0.02);
  ASSERT_EQ(m.size(), 2u);  // 2.0 has no partner within 0.02 s
  EXPECT_EQ(m[0], std::make_pair(0, 0));
  EXPECT_EQ(m[1], std::make_pair(2, 3));
}

TEST(Association, FindClosestIndexPicksNearest) {
  const std::vector<double> s{0.0, 1.0, 2.0, 3.0, 4.0};
  EXPECT_EQ(eval::findClosestIndex(s, 2.4), 2);
  EXPECT_EQ(eval::findClosestIndex(s, 2.6), 3);
  EXPECT_EQ(eval::findClosestIndex(s, -5), 0);
  EXPECT_EQ(eval::findClosestIndex(s, 50), 4);
  EXPECT_EQ(eval::findClosestIndex(s, 3.0), 3);
}

TEST(Ate, RigidlyTransformedCopyHasZeroError) {
  std::vector<io::TrajectoryEntry> gt, est;
  Pose T = Pose::Identity();
  T.linear() = Eigen::AngleAxisd(0.7, Vec3(0.3, 1, -0.2).normalized()).toRotationMatrix();
  T.translation() = Vec3(1, -2, 0.5);
  for (int i = 0; i < 50; ++i) {
    const Vec3 p(std::sin(i * 0.1), std::cos(i * 0.13), 0.01 * i);
    gt.push_back(entry(i * 0.1, p));
    est.push_back(entry(i * 0.1 + 0.005, T * p));
  }
  const auto r = eval::computeAte(gt, est);
  EXPECT_EQ(r.stats.count, 50);
  EXPECT_LT(r.stats.rmse, 1e-9);
}

TEST(Ate, KnownOffsetGivesKnownError) {
  // Alternating +-1 cm along z cannot be aligned away.
  std::vector<io::TrajectoryEntry> gt, est;
  for (int i = 0; i < 40; ++i) {
    const Vec3 p(i * 0.1, (i % 7) * 0.05, 0);
    gt.push_back(entry(i, p));
    est.push_back(entry(i, p + Vec3(0, 0, (i % 2 ? 0.01 : -0.01))));
  }
  const auto r = eval::computeAte(gt, est);
  // Alignment may tilt slightly towards the zig-zag but cannot remove it.
  EXPECT_LE(r.stats.rmse, 0.01 + 1e-9);
  EXPECT_GT(r.stats.rmse, 0.0095);
}

TEST(Ate, DisjointTimestampsAreAnInputError) {
  std::vector<io::TrajectoryEntry> gt{entry(0, Vec3::Zero()), entry(1, Vec3::Ones())};
  std::vector<io::TrajectoryEntry> est{entry(10, Vec3::Zero()), entry(11, Vec3::Ones())};
  EXPECT_THROW(eval::computeAte(gt, est), InputError);
}

TEST(Rpe, ConstantDriftPerSecondIsMeasured) {
  // Estimate moves 1 cm/s more than ground truth along x: RPE(1 s) = 1 cm for every pair.
  std::vector<io::TrajectoryEntry> gt, est;
  for (int i = 0; i <= 100; ++i) {
    const double t = i * 0.1;
    gt.push_back(entry(t, Vec3(0.2 * t, 0, 0)));
    est.push_back(entry(t, Vec3(0.21 * t, 0, 0)));
  }
  const auto r = eval::computeRpe(gt, est, 1.0);
  EXPECT_EQ(r.translation.count, 90);  // pairs whose partner is the last pose are dropped
  EXPECT_NEAR(r.translation.rmse, 0.01, 1e-9);
  EXPECT_NEAR(r.rotation_deg.rmse, 0.0, 1e-6);
}

}  // namespace
}  // namespace tkgslam
