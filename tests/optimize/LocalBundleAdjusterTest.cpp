#include <gtest/gtest.h>

#include "optimize/SyntheticBundle.h"

namespace tkgslam {
namespace {

double meanPointError(const test::SyntheticBundle& s) {
  double sum = 0;
  for (size_t p = 0; p < s.true_points.size(); ++p) sum += (s.problem.points[p] - s.true_points[p]).norm();
  return sum / double(s.true_points.size());
}

double translationError(const test::SyntheticBundle& s, size_t camera) {
  return (s.problem.poses[camera].translation() - s.true_poses[camera].translation()).norm();
}

// Eight keyframes (two fixed) and 300 points, a third of the observations monocular, 10 % gross
// outliers: the free poses and the points must come back to the truth from a perturbed start and
// the outliers be flagged - monocular and stereo residuals alike.
TEST(LocalBundleAdjuster, RecoversPosesAndPointsAndFlagsOutliers) {
  auto s = test::makeSyntheticBundle(8, 300, 0.10);
  const auto outlier = optimize::solveBundle(s.problem, s.K, {});
  for (size_t c = 2; c < s.true_poses.size(); ++c) {
    EXPECT_LT(translationError(s, c), 0.002) << "camera " << c;
    EXPECT_LT(rotationAngle(s.problem.poses[c].linear() * s.true_poses[c].linear().transpose()), 0.1 * M_PI / 180)
        << "camera " << c;
  }
  EXPECT_LT(meanPointError(s), 0.005);  // started 0.03 off
  int mono_flagged = 0, stereo_flagged = 0, wrong = 0;
  for (size_t k = 0; k < outlier.size(); ++k) {
    wrong += outlier[k] != s.is_outlier[k];
    if (outlier[k] && s.is_outlier[k]) (s.problem.observations[k].u_right < 0 ? mono_flagged : stereo_flagged)++;
  }
  EXPECT_LE(wrong, int(outlier.size() / 100));  // at most 1 % misclassified
  EXPECT_GT(mono_flagged, 40);
  EXPECT_GT(stereo_flagged, 100);
}

// Points seen only without depth still converge (their depth comes from the triangulation by the
// other keyframes): the zero third residual of a monocular observation must add nothing.
TEST(LocalBundleAdjuster, MonocularOnlyObservationsTriangulate) {
  auto s = test::makeSyntheticBundle(6, 150, 0.0, 0.2);
  for (auto& o : s.problem.observations) o.u_right = -1;
  optimize::solveBundle(s.problem, s.K, {});
  EXPECT_LT(meanPointError(s), 0.01);  // started 0.03 off
  for (size_t c = 2; c < s.true_poses.size(); ++c) EXPECT_LT(translationError(s, c), 0.005) << "camera " << c;
}

}  // namespace
}  // namespace tkgslam
