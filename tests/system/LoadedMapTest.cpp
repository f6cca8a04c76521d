// A run that starts in a saved map (SlamSystem::loadMap): found in it at once where it saw the
// same scene; a map the camera never sees costs a few frames, then a map segment of its own.
#include <opencv2/core.hpp>

#include <gtest/gtest.h>

#include "TestSupport.h"
#include "tkgslam/common/Error.h"
#include "tkgslam/io/ConfigFile.h"
#include "tkgslam/system/SlamSystem.h"

namespace tkgslam {
namespace {

SlamConfig orbConfig() {
  SlamConfig c = io::loadConfig((test::sourceDir() / "configs" / "tum_fr1.yaml").string());
  c.deterministic = true;
  c.dynamic.mode = DynamicMode::Orb;
  return c;
}

/// Frames [first, first + n) of fr1_xyz, optionally mirrored left-right (a scene no map of the
/// real one matches: ORB descriptors are not mirror-invariant).
std::vector<FrameOutcome> runFrames(SlamSystem& slam, int first, int n, bool mirrored) {
  io::TumDatasetOptions dopt;
  dopt.depth_factor = slam.config().depth.factor;
  const io::TumDataset dataset(test::fr1xyz().string(), dopt);
  std::vector<FrameOutcome> out;
  for (int i = first; i < first + n; ++i) {
    auto images = dataset.load(i);
    if (mirrored) {
      for (cv::Mat* m : {&images.bgr, &images.gray, &images.depth_m}) cv::flip(*m, *m, 1);
    }
    for (auto& f : slam.processFrame(images)) out.push_back(std::move(f));
  }
  for (auto& f : slam.finish()) out.push_back(std::move(f));
  return out;
}

class LoadedMap : public ::testing::Test {
 protected:
  void SetUp() override {
    TKGSLAM_REQUIRE_SHARED();
    SlamSystem first(orbConfig());
    runFrames(first, 0, 60, false);
    first.saveMap((tmp_ / "map.tkgmap").string());
    saved_keyframes_ = first.keyFrameCount();
    saved_points_ = first.mapPointCount();
  }
  test::TempDir tmp_;
  size_t saved_keyframes_ = 0;
  size_t saved_points_ = 0;
};

TEST_F(LoadedMap, TheSameSceneIsFoundOnTheFirstFrame) {
  SlamSystem slam(orbConfig());
  ASSERT_EQ(slam.loadMap((tmp_ / "map.tkgmap").string()), saved_keyframes_);
  const auto out = runFrames(slam, 60, 40, false);
  ASSERT_EQ(out.size(), 40u);
  EXPECT_TRUE(out.front().result.tracked);
  int tracked = 0, segments = 0;
  for (const auto& f : out) {
    tracked += f.result.tracked;
    segments += f.result.new_segment;
  }
  EXPECT_EQ(tracked, 40);
  EXPECT_EQ(segments, 0);
  // The map grew from the loaded one; the run's own keyframes are the only ones in its keyframe trajectory.
  EXPECT_GT(slam.keyFrameCount(), saved_keyframes_);
  EXPECT_EQ(slam.keyFrameTrajectory().size() + saved_keyframes_, slam.keyFrameCount());
  // Too late for another map.
  EXPECT_THROW(slam.loadMap((tmp_ / "map.tkgmap").string()), InputError);
}

TEST_F(LoadedMap, AMapTheCameraNeverSeesCostsAFewFramesThenANewSegment) {
  SlamSystem slam(orbConfig());
  slam.loadMap((tmp_ / "map.tkgmap").string());
  const auto out = runFrames(slam, 60, 40, true);
  ASSERT_EQ(out.size(), 40u);
  const int attempts = slam.config().tracking.relocalization_attempts;
  for (int i = 0; i < attempts; ++i) EXPECT_FALSE(out[i].result.tracked) << "frame " << i;
  EXPECT_TRUE(out[attempts].result.new_segment);
  int tracked = 0;
  for (const auto& f : out) tracked += f.result.tracked;
  EXPECT_EQ(tracked, 40 - attempts);
}

TEST_F(LoadedMap, LocalizationOnlyTracksWithoutChangingTheMap) {
  SlamSystem slam(orbConfig());
  slam.loadMap((tmp_ / "map.tkgmap").string(), true);
  const auto out = runFrames(slam, 60, 40, false);
  ASSERT_EQ(out.size(), 40u);
  int tracked = 0;
  for (const auto& f : out) {
    tracked += f.result.tracked;
    EXPECT_FALSE(f.result.new_keyframe);
  }
  EXPECT_EQ(tracked, 40);
  EXPECT_EQ(slam.keyFrameCount(), saved_keyframes_);
  EXPECT_EQ(slam.mapPointCount(), saved_points_);
  EXPECT_TRUE(slam.keyFrameTrajectory().empty());
  EXPECT_EQ(slam.trajectory().size(), 40u);
}

TEST_F(LoadedMap, LocalizationFindsTheCameraTryingOnlyTheMostSimilarKeyFrame) {
  // The index ranks the loaded keyframes by their words; one candidate is enough where the
  // camera sees what the map saw - at the start of the mapped frames as at their end.
  for (int first : {0, 30, 60}) {
    SlamConfig c = orbConfig();
    c.tracking.relocalization_candidates = 1;
    SlamSystem slam(c);
    slam.loadMap((tmp_ / "map.tkgmap").string(), true);
    const auto out = runFrames(slam, first, 10, false);
    ASSERT_EQ(out.size(), 10u);
    for (const auto& f : out) EXPECT_TRUE(f.result.tracked) << "from frame " << first << ", frame " << f.index;
  }
}

TEST_F(LoadedMap, LocalizationOnlyKeepsRelocalisingInsteadOfStartingASegment) {
  SlamSystem slam(orbConfig());
  slam.loadMap((tmp_ / "map.tkgmap").string(), true);
  auto out = runFrames(slam, 60, 20, true);
  ASSERT_EQ(out.size(), 20u);
  for (const auto& f : out) {
    EXPECT_FALSE(f.result.tracked);
    EXPECT_FALSE(f.result.new_segment);
  }
  EXPECT_EQ(slam.keyFrameCount(), saved_keyframes_);
  EXPECT_EQ(slam.mapPointCount(), saved_points_);
  // The camera comes back to the mapped scene: found again at once.
  for (auto& f : runFrames(slam, 80, 10, false)) EXPECT_TRUE(f.result.tracked);
}

}  // namespace
}  // namespace tkgslam
