#include <cmath>

#include <gtest/gtest.h>

#include "TestSupport.h"
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

/// The message of computeAte's InputError for these trajectories.
std::string ateError(const std::vector<io::TrajectoryEntry>& gt, const std::vector<io::TrajectoryEntry>& est) {
  return test::inputErrorOf([&] { eval::computeAte(gt, est); });
}

// When nothing pairs up, the stamps often say why: another unit (EuRoC's nanoseconds), no overlap
// in time, or too few poses.
TEST(Ate, TheErrorWhenNothingPairsUpSaysWhy) {
  std::vector<io::TrajectoryEntry> gt, ns, ms, later;
  for (int i = 0; i < 20; ++i) {
    const double t = 1305031102.0 + 0.1 * i;
    gt.push_back(entry(t, Vec3(0.1 * i, 0, 0)));
    ns.push_back(entry(t * 1e9, Vec3(0.1 * i, 0, 0)));
    ms.push_back(entry(t * 1e3, Vec3(0.1 * i, 0, 0)));
    later.push_back(entry(t + 100, Vec3(0.1 * i, 0, 0)));
  }
  EXPECT_NE(ateError(gt, ns).find("the estimate's timestamps are 1e+09 times the ground truth's - nanoseconds?"),
            std::string::npos)
      << ateError(gt, ns);
  EXPECT_NE(ateError(ms, gt).find("the ground truth's timestamps are 1000 times the estimate's - milliseconds?"),
            std::string::npos)
      << ateError(ms, gt);
  EXPECT_NE(ateError(gt, later).find("which do not overlap"), std::string::npos) << ateError(gt, later);
  EXPECT_NE(ateError(gt, {gt[3]}).find(": the estimate has 1 pose(s)"), std::string::npos) << ateError(gt, {gt[3]});
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

// evaluate_rpe.py's --delta_unit: the pair's second pose is delta frames, metres or degrees on.
TEST(Rpe, DeltaInFramesMetresAndDegreesTravelledAlongTheEstimate) {
  // Both turn 2 deg and move 1 cm per frame (0.1 s) along their own x; the estimate moves 1.1 cm.
  std::vector<io::TrajectoryEntry> gt, est, est_doubled;
  Pose P = Pose::Identity(), Q = Pose::Identity(), D = Pose::Identity();
  const Eigen::AngleAxisd turn(2.0 * M_PI / 180.0, Vec3::UnitZ());
  const auto add = [](std::vector<io::TrajectoryEntry>& traj, double t, const Pose& T_wc) {
    traj.push_back(entry(t, T_wc.translation(), Eigen::Quaterniond(T_wc.linear())));
  };
  for (int i = 0; i < 30; ++i) {
    add(gt, 0.1 * i, Q);
    add(est, 0.1 * i, P);
    add(est_doubled, 0.1 * i, D);
    Pose step = Pose::Identity();
    step.linear() = turn.toRotationMatrix();
    step.translation() = Vec3(0.01, 0, 0);
    Q = Q * step;
    step.translation() = Vec3(0.011, 0, 0);
    P = P * step;
    step.translation() = Vec3(0.022, 0, 0);
    D = D * step;
  }
  const auto rpe = [&](const std::vector<io::TrajectoryEntry>& e, double delta, eval::DeltaUnit unit,
                       double scale = 1.0) { return eval::computeRpe(gt, e, eval::RpeOptions{delta, unit, scale}); };
  // One frame on: 1 mm; pairs whose partner is the last pose are dropped (28 of 30).
  auto r = rpe(est, 1, eval::DeltaUnit::Frames);
  EXPECT_EQ(r.translation.count, 28);
  EXPECT_NEAR(r.translation.rmse, 0.001, 1e-9);
  EXPECT_NEAR(r.rotation_deg.rmse, 0.0, 1e-6);
  // k frames on, the two differ by 1 mm along each of the k steps, which turn 2 deg one to the next:
  // a chord of k mm x sin(k deg) / (k sin(1 deg)).
  const auto chord_mm = [](int k) { return 0.001 * std::sin(k * M_PI / 180.0) / std::sin(M_PI / 180.0); };
  EXPECT_NEAR(rpe(est, 3, eval::DeltaUnit::Frames).translation.rmse, chord_mm(3), 1e-12);
  EXPECT_NEAR(rpe(est, 6, eval::DeltaUnit::Degrees).translation.rmse, chord_mm(3), 1e-12);
  EXPECT_NEAR(rpe(est, 6 * M_PI / 180.0, eval::DeltaUnit::Radians).translation.rmse, chord_mm(3), 1e-12);
  EXPECT_NEAR(rpe(est, 0.055, eval::DeltaUnit::Metres).translation.rmse, chord_mm(5), 1e-12);  // 5 steps of 1.1 cm
  EXPECT_NEAR(rpe(est, 0.5, eval::DeltaUnit::Seconds).translation.rmse, chord_mm(5), 1e-12);
  // The scale applies to the error, not to the distance travelled: 0.11 m of the doubled estimate
  // is 5 of its 2.2 cm steps, and halved they are 1.1 cm steps again.
  EXPECT_NEAR(rpe(est_doubled, 0.11, eval::DeltaUnit::Metres, 0.5).translation.rmse, chord_mm(5), 1e-12);
  EXPECT_EQ(eval::parseDeltaUnit("deg"), eval::DeltaUnit::Degrees);
  EXPECT_THROW(eval::parseDeltaUnit("ms"), InputError);
}

}  // namespace
}  // namespace tkgslam
