#include <cmath>

#include <gtest/gtest.h>

#include "tkgslam/optimize/PoseGraphOptimizer.h"

namespace tkgslam {
namespace {

constexpr double kDeg = M_PI / 180.0;

// World -> camera poses of a camera moving along a 2 m arc, turning as it goes.
std::vector<Pose> trueChain(int n) {
  std::vector<Pose> out;
  for (int k = 0; k < n; ++k) {
    Pose T_wc = Pose::Identity();
    T_wc.linear() = Eigen::AngleAxisd(0.05 * k, Vec3::UnitY()).toRotationMatrix();
    T_wc.translation() = Vec3(0.1 * k, 0.02 * k, 0.05 * std::sin(0.3 * k));
    out.push_back(T_wc.inverse());
  }
  return out;
}

Pose offset(double deg, const Vec3& t) {
  Pose G = Pose::Identity();
  G.linear() = Eigen::AngleAxisd(deg * kDeg, Vec3(0.3, 1, 0.2).normalized()).toRotationMatrix();
  G.translation() = t;
  return G;
}

// A forked map: the keyframes from `kFork` on sit in a rotated and shifted copy of the world
// (what a few wrong frames do). Chain edges carry the relative poses as estimated - exact within
// each branch, wrong across the fork - weighted like shared map points (within a branch a
// keyframe shares hundreds with each of several neighbours: 1000 for the one chain edge here),
// and a loop edge carries the true relative pose of the last and the first keyframe.
struct ForkedChain {
  static constexpr int kNodes = 20;
  static constexpr int kFork = 12;
  std::vector<Pose> truth = trueChain(kNodes);
  optimize::PoseGraph graph;

  explicit ForkedChain(double across_fork_weight) {
    const Pose G = offset(15, Vec3(0.2, -0.1, 0.05));  // maps the true world into the forked one
    for (int k = 0; k < kNodes; ++k) {
      graph.poses.push_back(k < kFork ? truth[k] : Pose(truth[k] * G.inverse()));
      graph.fixed.push_back(k == 0);
    }
    for (int k = 1; k < kNodes; ++k) {
      const double w = k == kFork ? across_fork_weight : 1000.0;
      graph.edges.push_back({k, k - 1, graph.poses[k] * graph.poses[k - 1].inverse(), w});
    }
    graph.edges.push_back({kNodes - 1, 0, truth[kNodes - 1] * truth[0].inverse(), 1e5});
  }
  double worstTranslationError() const {
    double worst = 0;
    for (int k = 0; k < kNodes; ++k) {
      worst = std::max(worst, (graph.poses[k].inverse().translation() - truth[k].inverse().translation()).norm());
    }
    return worst;
  }
};

// The weak link across the fork takes the whole correction: both branches end up where they
// truly are (the fixed first keyframe holds the gauge).
TEST(PoseGraphOptimizer, LoopEdgeMovesTheForkedBranchBackWhereItsLinkIsWeak) {
  ForkedChain chain(/*across_fork_weight=*/1.0);
  ASSERT_GT(chain.worstTranslationError(), 0.2);
  ASSERT_TRUE(optimize::optimizePoseGraph(chain.graph));
  EXPECT_LT(chain.worstTranslationError(), 0.01);
  for (int k = 0; k < ForkedChain::kNodes; ++k) {
    const Mat3 dR = chain.graph.poses[k].linear() * chain.truth[k].linear().transpose();
    EXPECT_LT(rotationAngle(dR), 0.5 * kDeg) << "keyframe " << k;
  }
  EXPECT_TRUE(chain.graph.poses[0].isApprox(chain.truth[0]));  // fixed
}

// With every edge equally strong the correction is spread over the chain instead: the loop is
// closed, but keyframes in between stay off. (Why the edges are weighted by shared points.)
TEST(PoseGraphOptimizer, EqualWeightsSpreadTheCorrectionOverTheChain) {
  ForkedChain chain(/*across_fork_weight=*/1000.0);
  ASSERT_TRUE(optimize::optimizePoseGraph(chain.graph));
  const int last = ForkedChain::kNodes - 1;
  EXPECT_LT((chain.graph.poses[last].inverse().translation() - chain.truth[last].inverse().translation()).norm(), 0.01);
  EXPECT_GT(chain.worstTranslationError(), 0.03);
}

TEST(PoseGraphOptimizer, RefusesAGraphWithoutAFixedNode) {
  ForkedChain chain(1.0);
  chain.graph.fixed.assign(chain.graph.fixed.size(), 0);
  const auto before = chain.graph.poses;
  EXPECT_FALSE(optimize::optimizePoseGraph(chain.graph));
  for (size_t k = 0; k < before.size(); ++k) EXPECT_TRUE(chain.graph.poses[k].isApprox(before[k]));
}

}  // namespace
}  // namespace tkgslam
