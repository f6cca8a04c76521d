#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "TestSupport.h"
#include "loop/KeyFrameWithPoints.h"
#include "tkgslam/camera/PinholeCamera.h"
#include "tkgslam/data/FrameFeatures.h"
#include "tkgslam/data/KeyFrame.h"
#include "tkgslam/data/Map.h"
#include "tkgslam/data/MapPoint.h"
#include "tkgslam/feature/OrbExtractor.h"
#include "tkgslam/io/ConfigFile.h"
#include "tkgslam/io/TrajectoryFile.h"
#include "tkgslam/io/TumDataset.h"
#include "tkgslam/loop/LoopCloser.h"

namespace tkgslam {
namespace {

constexpr double kDeg = M_PI / 180.0;

// A map built from real fr1_xyz frames at their ground-truth poses (relative to frame 0): an old
// keyframe at frame 0, and new keyframes a second later that see the same desk. With `fork` the
// new keyframes and their points sit in a copy of the world rotated by 10 degrees and shifted by
// 15 cm - what a few frames tracked on a person the detector missed leave behind - and share no
// point with the old keyframe, so local BA cannot see the disagreement.
class ForkedMap : public ::testing::Test {
 protected:
  void SetUp() override {
    TKGSLAM_REQUIRE_SHARED();
    config_ = io::loadConfig((test::sourceDir() / "configs" / "tum_fr1.yaml").string());
    config_.deterministic = true;
    config_.loop.min_keyframe_gap = 1;
    config_.loop.confirm = true;
    camera_ = std::make_unique<camera::PinholeCamera>(config_.camera);
    extractor_ = std::make_unique<feature::OrbExtractor>(config_.orb);
    dataset_ = std::make_unique<io::TumDataset>(test::fr1xyz().string());
    truth_ = io::readTumTrajectory((test::fr1xyz() / "groundtruth.txt").string());
  }

  // World -> camera at frame i, the world being camera 0 (ground truth, nearest stamp).
  Pose truePose(int i) const { return (truthAt(dataset_->timestamp(0)).inverse() * truthAt(dataset_->timestamp(i))).inverse(); }

  Pose truthAt(double t) const {
    const auto it = std::min_element(truth_.begin(), truth_.end(), [t](const auto& a, const auto& b) {
      return std::abs(a.timestamp - t) < std::abs(b.timestamp - t);
    });
    return it->pose();
  }

  // A keyframe of frame i at pose T_cw with a map point for every keypoint with depth.
  std::shared_ptr<data::KeyFrame> addKeyFrame(int i, const Pose& T_cw) {
    const auto images = dataset_->load(i);
    auto features = data::makeFrameFeatures(extractor_->extract(images.gray), images.bgr, images.depth_m, *camera_,
                                            config_.depth);
    return test::addKeyFrameWithPoints(map_, features, i, images.timestamp, T_cw, *camera_, extractor_->pyramid());
  }

  // The old keyframe, then two new ones (frames 30 and 33; the second observes the first's points
  // so the two are covisible, as consecutive keyframes are), in the forked world or not.
  // With `others`, keyframes of those frames (made after the old keyframe, before the new ones)
  // at their true poses, chained to the old keyframe: more candidates for a loop, each in the true
  // world.
  void build(bool fork, const std::vector<int>& others = {}) {
    old_ = addKeyFrame(0, truePose(0));
    old_->not_erase = true;
    const data::KeyFrame* previous = old_.get();
    for (const int i : others) {
      auto kf = addKeyFrame(i, truePose(i));
      kf->parent = const_cast<data::KeyFrame*>(previous);  // a spanning tree, as mapping makes one
      previous = kf.get();
    }
    G_ = Pose::Identity();
    if (fork) {
      G_.linear() = Eigen::AngleAxisd(10 * kDeg, Vec3(0.2, 1, 0.1).normalized()).toRotationMatrix();
      G_.translation() = Vec3(0.15, -0.05, 0.03);
    }
    first_ = addKeyFrame(30, truePose(30) * G_.inverse());
    second_ = addKeyFrame(33, truePose(33) * G_.inverse());
    for (size_t k = 0; k < first_->map_points.size() && k < second_->map_points.size(); k += 2) {
      // Share every other point of the first keyframe with the second (covisibility only).
      const auto& mp = first_->map_points[k];
      if (mp && !second_->map_points[k]) {
        mp->observations[second_.get()] = int(k);
        second_->addMapPoint(mp, int(k));
      }
    }
    first_->updateConnections();
    second_->updateConnections();
    ASSERT_EQ(first_->connections.count(old_.get()), 0u);
  }

  // A keyframe of frame 31 in the forked world (made after the two new ones, so processed in
  // between them in the tests) that detects no loop: it shares points with the old keyframe, so the
  // old one is no candidate (covisible), and the new ones agree with it.
  std::shared_ptr<data::KeyFrame> addKeyFrameThatFindsNoLoop() {
    auto kf = addKeyFrame(31, truePose(31) * G_.inverse());
    int shared = 0;
    for (size_t k = 0; k < kf->map_points.size() && k < old_->map_points.size() && shared < 30; ++k) {
      const auto& mp = old_->map_points[k];
      if (!mp || kf->map_points[k]) continue;
      mp->observations[kf.get()] = int(k);
      kf->addMapPoint(mp, int(k));
      ++shared;
    }
    kf->updateConnections();
    EXPECT_EQ(kf->connections.count(old_.get()), 1u);
    return kf;
  }

  // Median reprojection error (pixels) of the new keyframes' observations of the old keyframe's
  // points (fused into them when the loop closed).
  double medianReprojectionError() const {  // (EXPECTs enough observations)
    std::vector<double> e;
    for (const auto& kf : {first_, second_}) {
      const auto& F = *kf->features;
      for (size_t k = 0; k < kf->map_points.size(); ++k) {
        const auto& mp = kf->map_points[k];
        if (!mp || mp->bad || !mp->observations.count(old_.get())) continue;
        const Vec3 pc = kf->T_cw() * mp->pos_w;
        if (pc.z() <= 0) continue;
        const Vec2 uv(camera_->fx() * pc.x() / pc.z() + camera_->cx(), camera_->fy() * pc.y() / pc.z() + camera_->cy());
        e.push_back((uv - Vec2(F.ideal[k].pt.x, F.ideal[k].pt.y)).norm());
      }
    }
    EXPECT_GE(e.size(), 20u) << "too few fused observations to measure";
    if (e.empty()) return 0;
    std::nth_element(e.begin(), e.begin() + e.size() / 2, e.end());
    return e[e.size() / 2];
  }

  static double centreError(const data::KeyFrame& kf, const Pose& T_cw_true) {
    return (kf.centre() - T_cw_true.inverse().translation()).norm();
  }

  SlamConfig config_;
  std::unique_ptr<camera::PinholeCamera> camera_;
  std::unique_ptr<feature::OrbExtractor> extractor_;
  std::unique_ptr<io::TumDataset> dataset_;
  std::vector<io::TrajectoryEntry> truth_;
  data::Map map_;
  Pose G_ = Pose::Identity();  ///< true world -> forked world
  std::shared_ptr<data::KeyFrame> old_, first_, second_;
};

TEST_F(ForkedMap, AConfirmedLoopPutsTheForkedKeyframesBackWhereTheCameraWas) {
  build(/*fork=*/true);
  ASSERT_GT(centreError(*second_, truePose(33)), 0.1);
  loop::LoopCloser closer(map_, *camera_, extractor_->pyramid(), config_);
  EXPECT_FALSE(closer.process(first_));  // found, waiting for the next keyframe to confirm
  EXPECT_EQ(closer.stats().detected, 1);
  ASSERT_TRUE(closer.process(second_));
  EXPECT_EQ(closer.stats().closed, 1);
  EXPECT_GT(closer.stats().last_correction_m, 0.1);

  // Both new keyframes within 2 cm and 1 degree of the truth; the old one did not move.
  for (const auto& [kf, frame] : {std::pair{first_, 30}, std::pair{second_, 33}}) {
    EXPECT_LT(centreError(*kf, truePose(frame)), 0.02) << "frame " << frame;
    EXPECT_LT(rotationAngle(kf->T_cw().linear() * truePose(frame).linear().transpose()), 1 * kDeg) << "frame " << frame;
  }
  EXPECT_TRUE(old_->T_cw().isApprox(truePose(0)));
  // The new keyframes' points moved with them: seen from the true pose they lie on their keypoints'
  // depth again (median over the points with depth, within 2 cm).
  std::vector<double> depth_errors;
  const auto& F = *second_->features;
  for (int k = 0; k < F.size(); ++k) {
    const auto& mp = second_->map_points[k];
    if (mp && !mp->bad && F.hasDepth(k)) depth_errors.push_back(std::abs((truePose(33) * mp->pos_w).z() - F.depth[k]));
  }
  ASSERT_GT(depth_errors.size(), 100u);
  std::nth_element(depth_errors.begin(), depth_errors.begin() + depth_errors.size() / 2, depth_errors.end());
  EXPECT_LT(depth_errors[depth_errors.size() / 2], 0.02);
  // The old keyframe's points were fused into the new ones: the two sides are covisible now.
  EXPECT_GT(second_->connections.count(old_.get()) + first_->connections.count(old_.get()), 0u);
}

// The pose graph moves each keyframe rigidly with its points, so what it leaves is inconsistent
// where the two sides meet: the old keyframe's points fused into the new keyframes sit where the
// new keyframes see them only roughly. The global bundle adjustment after it refits keyframes
// and points to all the observations: the new keyframes' reprojection error drops.
constexpr double kRefitPx = 1.4;  // median px: above without global BA, below with it

TEST_F(ForkedMap, GlobalBundleAdjustmentRefitsTheClosedLoop) {
  build(/*fork=*/true);
  config_.loop.global_ba_iterations = 10;
  loop::LoopCloser closer(map_, *camera_, extractor_->pyramid(), config_);
  closer.process(first_);
  ASSERT_TRUE(closer.process(second_));
  EXPECT_EQ(closer.stats().global_bundles, 1);
  EXPECT_TRUE(old_->T_cw().isApprox(truePose(0)));  // the gauge did not move
  std::printf("with global BA: %.3f px; %.4f m (frame 30), %.4f m (frame 33)\n", medianReprojectionError(), centreError(*first_, truePose(30)), centreError(*second_, truePose(33)));
  EXPECT_LT(medianReprojectionError(), kRefitPx);
  EXPECT_LT(centreError(*second_, truePose(33)), 0.02);
}

TEST_F(ForkedMap, WithoutGlobalBundleAdjustmentThePoseGraphLeavesItLessConsistent) {
  build(/*fork=*/true);
  config_.loop.global_ba_iterations = 0;
  loop::LoopCloser closer(map_, *camera_, extractor_->pyramid(), config_);
  closer.process(first_);
  ASSERT_TRUE(closer.process(second_));
  EXPECT_EQ(closer.stats().global_bundles, 0);
  std::printf("without global BA: %.3f px; %.4f m (frame 30), %.4f m (frame 33)\n", medianReprojectionError(), centreError(*first_, truePose(30)), centreError(*second_, truePose(33)));
  EXPECT_GT(medianReprojectionError(), kRefitPx);
}

TEST_F(ForkedMap, WithoutConfirmationTheFirstDetectionCloses) {
  build(/*fork=*/true);
  config_.loop.confirm = false;
  loop::LoopCloser closer(map_, *camera_, extractor_->pyramid(), config_);
  ASSERT_TRUE(closer.process(first_));
  EXPECT_LT(centreError(*first_, truePose(30)), 0.02);
  EXPECT_LT(centreError(*second_, truePose(33)), 0.02);  // moved with it: covisible
}

TEST_F(ForkedMap, WithConfirmationASingleDetectionIsNotEnough) {
  build(/*fork=*/true);
  const Pose before = first_->T_cw();
  loop::LoopCloser closer(map_, *camera_, extractor_->pyramid(), config_);
  EXPECT_FALSE(closer.process(first_));
  EXPECT_EQ(closer.stats().detected, 1);
  EXPECT_EQ(closer.stats().closed, 0);
  EXPECT_TRUE(first_->T_cw().isApprox(before));
}

TEST_F(ForkedMap, ADetectionWaitsAFewKeyframesForItsConfirmation) {
  // A keyframe in between that sees too little of the old place (a person in front of it) does not
  // cancel the first detection: the next one confirms it (loop.confirm_within, 3).
  build(/*fork=*/true);
  const auto between = addKeyFrameThatFindsNoLoop();
  loop::LoopCloser closer(map_, *camera_, extractor_->pyramid(), config_);
  EXPECT_FALSE(closer.process(first_));
  EXPECT_FALSE(closer.process(between));
  EXPECT_EQ(closer.stats().detected, 1);
  ASSERT_TRUE(closer.process(second_));
  EXPECT_LT(centreError(*second_, truePose(33)), 0.02);
}

TEST_F(ForkedMap, WithConfirmationByTheNextKeyframeOnlyOneInBetweenCancelsIt) {
  build(/*fork=*/true);
  const auto between = addKeyFrameThatFindsNoLoop();
  config_.loop.confirm_within = 1;
  loop::LoopCloser closer(map_, *camera_, extractor_->pyramid(), config_);
  EXPECT_FALSE(closer.process(first_));
  EXPECT_FALSE(closer.process(between));
  EXPECT_FALSE(closer.process(second_));  // detected again, but now waiting for its own confirmation
  EXPECT_EQ(closer.stats().detected, 2);
  EXPECT_EQ(closer.stats().closed, 0);
}

TEST_F(ForkedMap, WhereTheMapAlreadyHasTheCameraNothingMoves) {
  build(/*fork=*/false);
  const Pose before = second_->T_cw();
  loop::LoopCloser closer(map_, *camera_, extractor_->pyramid(), config_);
  EXPECT_FALSE(closer.process(first_));
  EXPECT_FALSE(closer.process(second_));
  EXPECT_GE(closer.stats().consistent, 2);  // the loop was found, and agreed with the map
  EXPECT_EQ(closer.stats().detected, 0);
  EXPECT_TRUE(second_->T_cw().isApprox(before));
}

// Frames 60, 90, ..., 660 of fr1_xyz: the same desk from elsewhere on the camera's path.
std::vector<int> otherFrames() {
  std::vector<int> out;
  for (int i = 60; i <= 660; i += 30) out.push_back(i);
  return out;
}

TEST_F(ForkedMap, InALargerMapOnlyTheMostSimilarKeyFramesAreMatched) {
  // 22 candidates, the 2 most like each new keyframe by words matched: the loop is still found
  // and closed.
  build(/*fork=*/true, otherFrames());
  config_.loop.word_candidates = 2;
  loop::LoopCloser closer(map_, *camera_, extractor_->pyramid(), config_);
  EXPECT_FALSE(closer.process(first_));
  ASSERT_TRUE(closer.process(second_));
  EXPECT_EQ(closer.stats().candidates_considered, 4);
  EXPECT_EQ(closer.stats().vocabulary_trainings, 1);  // the map did not double in between
  EXPECT_LT(centreError(*first_, truePose(30)), 0.02);
  EXPECT_LT(centreError(*second_, truePose(33)), 0.02);
}

TEST_F(ForkedMap, WithoutTheWordIndexEveryCandidateIsMatched) {
  build(/*fork=*/true, otherFrames());
  config_.loop.word_candidates = 0;
  loop::LoopCloser closer(map_, *camera_, extractor_->pyramid(), config_);
  EXPECT_FALSE(closer.process(first_));
  ASSERT_TRUE(closer.process(second_));
  EXPECT_EQ(closer.stats().candidates_considered, 44);
  EXPECT_EQ(closer.stats().vocabulary_trainings, 0);
}

TEST_F(ForkedMap, DisabledLoopClosingLeavesTheForkAlone) {
  build(/*fork=*/true);
  config_.loop.enabled = false;
  loop::LoopCloser closer(map_, *camera_, extractor_->pyramid(), config_);
  EXPECT_FALSE(closer.process(first_));
  EXPECT_FALSE(closer.process(second_));
  EXPECT_EQ(closer.stats().keyframes_checked, 0);
  EXPECT_GT(centreError(*second_, truePose(33)), 0.1);
}

}  // namespace
}  // namespace tkgslam
