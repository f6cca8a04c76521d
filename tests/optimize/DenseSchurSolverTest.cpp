#include "tkgslam/optimize/DenseSchurSolver.h"

#include <cmath>
#include <vector>

#include <ceres/ceres.h>
#include <gtest/gtest.h>

#include "optimize/SyntheticBundle.h"
#include "tkgslam/optimize/ReprojectionCost.h"

namespace tkgslam {
namespace {

// The same problem solved by Ceres (DENSE_SCHUR, the quaternion manifold, Huber as requested): the
// reference our solver must match. Returns Ceres' final cost.
double solveWithCeres(optimize::BundleProblem& pb, const optimize::PinholeIntrinsics& K, int iterations, bool robust) {
  std::vector<Eigen::Quaterniond> q;
  std::vector<Vec3> t;
  for (const auto& T : pb.poses) {
    q.emplace_back(T.linear());
    t.push_back(T.translation());
  }
  ceres::Problem problem;
  for (const auto& o : pb.observations) {
    const optimize::BundleOptions chi2;  // local mapping's thresholds
    ceres::LossFunction* loss =
        robust ? new ceres::HuberLoss(std::sqrt(o.u_right >= 0 ? chi2.chi2_stereo : chi2.chi2_mono)) : nullptr;
    problem.AddResidualBlock(new optimize::ReprojectionCost(o, K), loss, q[size_t(o.camera)].coeffs().data(),
                             t[size_t(o.camera)].data(), pb.points[size_t(o.point)].data());
  }
  for (size_t c = 0; c < pb.poses.size(); ++c) {
    problem.SetManifold(q[c].coeffs().data(), new ceres::EigenQuaternionManifold);
    if (pb.fixed_pose[c]) {
      problem.SetParameterBlockConstant(q[c].coeffs().data());
      problem.SetParameterBlockConstant(t[c].data());
    }
  }
  ceres::Solver::Options so;
  so.linear_solver_type = ceres::DENSE_SCHUR;
  so.max_num_iterations = iterations;
  ceres::Solver::Summary summary;
  ceres::Solve(so, &problem, &summary);
  for (size_t c = 0; c < pb.poses.size(); ++c) {
    pb.poses[c].linear() = q[c].normalized().toRotationMatrix();
    pb.poses[c].translation() = t[c];
  }
  return summary.final_cost;
}

optimize::DenseSchurSettings settings(int iterations, bool robust) {
  optimize::DenseSchurSettings s;
  s.iterations = iterations;
  s.robust = robust;
  const optimize::BundleOptions chi2;  // local mapping's thresholds
  s.huber_mono = std::sqrt(chi2.chi2_mono);
  s.huber_stereo = std::sqrt(chi2.chi2_stereo);
  return s;
}

struct Difference {
  double pose_m = 0, pose_rad = 0, point_m = 0;
};

Difference largestDifference(const optimize::BundleProblem& a, const optimize::BundleProblem& b) {
  Difference d;
  for (size_t c = 0; c < a.poses.size(); ++c) {
    d.pose_m = std::max(d.pose_m, (a.poses[c].translation() - b.poses[c].translation()).norm());
    d.pose_rad = std::max(d.pose_rad, rotationAngle(a.poses[c].linear() * b.poses[c].linear().transpose()));
  }
  for (size_t p = 0; p < a.points.size(); ++p) d.point_m = std::max(d.point_m, (a.points[p] - b.points[p]).norm());
  return d;
}

// From the same perturbed start, without outliers: the minimum our solver reaches is Ceres' - the
// cost to 1e-6, poses to 1e-6 m / rad, points to 1e-5 m.
TEST(DenseSchurSolver, ReachesCeresMinimum) {
  const auto s = test::makeSyntheticBundle(12, 400, 0.0);
  auto ours = s.problem, theirs = s.problem;
  const auto summary = optimize::solveDenseSchur(ours, {}, s.K, settings(20, false));
  const double ceres_cost = solveWithCeres(theirs, s.K, 20, false);
  EXPECT_LT(summary.final_cost, 0.01 * summary.initial_cost);
  EXPECT_NEAR(summary.final_cost, ceres_cost, 1e-6 * ceres_cost);
  const auto d = largestDifference(ours, theirs);
  EXPECT_LT(d.pose_m, 1e-6);
  EXPECT_LT(d.pose_rad, 1e-6);
  EXPECT_LT(d.point_m, 1e-5);
}

// With 5 % gross outliers under the Huber loss (local mapping's first pass): as low a cost as
// Ceres' (to 1e-6) and the same poses to 2e-5 m / rad.
TEST(DenseSchurSolver, RobustLossMatchesCeres) {
  const auto s = test::makeSyntheticBundle(12, 400, 0.05);
  auto ours = s.problem, theirs = s.problem;
  const auto summary = optimize::solveDenseSchur(ours, {}, s.K, settings(20, true));
  const double ceres_cost = solveWithCeres(theirs, s.K, 20, true);
  EXPECT_LT(summary.final_cost, 0.5 * summary.initial_cost);  // the outliers' cost stays
  EXPECT_LT(summary.final_cost, ceres_cost * (1 + 1e-6));
  const auto d = largestDifference(ours, theirs);
  EXPECT_LT(d.pose_m, 2e-5);
  EXPECT_LT(d.pose_rad, 2e-5);
}

// Excluded observations count for nothing: solving with the outliers excluded gives what solving
// the problem without them gives, and the held poses do not move by a bit.
TEST(DenseSchurSolver, ExcludedObservationsAndFixedPosesStayOut) {
  const auto s = test::makeSyntheticBundle(8, 200, 0.10);
  auto with_excluded = s.problem;
  std::vector<char> excluded(s.is_outlier.begin(), s.is_outlier.end());
  optimize::solveDenseSchur(with_excluded, excluded, s.K, settings(10, false));
  auto without = s.problem;
  without.observations.clear();
  for (size_t k = 0; k < s.problem.observations.size(); ++k)
    if (!s.is_outlier[k]) without.observations.push_back(s.problem.observations[k]);
  optimize::solveDenseSchur(without, {}, s.K, settings(10, false));
  for (size_t c = 0; c < s.problem.poses.size(); ++c) {
    EXPECT_LT((with_excluded.poses[c].translation() - without.poses[c].translation()).norm(), 1e-12);
    EXPECT_LT((with_excluded.poses[c].translation() - s.true_poses[c].translation()).norm(), 0.002) << "camera " << c;
  }
  for (size_t c = 0; c < 2; ++c) EXPECT_TRUE(with_excluded.poses[c].matrix() == s.problem.poses[c].matrix());
}

// A point seen only by the held keyframes is still solved (Ceres too optimises it); a problem with
// every observation excluded is left as it is.
TEST(DenseSchurSolver, PointsOfHeldKeyframesAndEmptyProblems) {
  auto s = test::makeSyntheticBundle(4, 50, 0.0);
  for (auto& f : s.problem.fixed_pose) f = 1;
  s.problem.poses = s.true_poses;
  const auto summary = optimize::solveDenseSchur(s.problem, {}, s.K, settings(10, false));
  EXPECT_GT(summary.accepted, 0);
  double error = 0;  // started 0.03 m off; far points keep their depth noise (0.1 px at 3 m: 2 cm)
  for (size_t p = 0; p < s.true_points.size(); ++p) error += (s.problem.points[p] - s.true_points[p]).norm();
  EXPECT_LT(error / double(s.true_points.size()), 0.008);
  auto untouched = s.problem;
  const auto none = optimize::solveDenseSchur(untouched, std::vector<char>(s.problem.observations.size(), 1), s.K,
                                              settings(10, false));
  EXPECT_EQ(none.iterations, 0);
  EXPECT_TRUE(untouched.points == s.problem.points);
}

}  // namespace
}  // namespace tkgslam
