// Derived settings of the configuration: which schedules move the boxes by optical flow.
#include <gtest/gtest.h>

#include "tkgslam/system/SlamConfig.h"

namespace tkgslam {
namespace {

DynamicParams schedule(DynamicMode mode, int every, int latency, bool lookahead, int tiles = 1) {
  DynamicParams d;
  d.mode = mode;
  d.detect_every = every;
  d.detector_latency = latency;
  d.lookahead = lookahead;
  d.detector_tiles = tiles;
  return d;
}

TEST(SlamConfig, BoxFlowAutoFollowsOnlyFramesTrackedWithoutADetectionOfTheirOwn) {
  const auto TKG = DynamicMode::TKG;
  // Every frame detected before it is tracked: synchronously, or one frame ahead (run --fast).
  EXPECT_FALSE(schedule(TKG, 1, 0, false).usesBoxFlow());
  EXPECT_FALSE(schedule(TKG, 1, 1, true).usesBoxFlow());
  // Frames skipped, tiled, or boxed before their detection arrives.
  EXPECT_TRUE(schedule(TKG, 2, 0, false).usesBoxFlow());
  EXPECT_TRUE(schedule(TKG, 1, 1, false).usesBoxFlow());
  EXPECT_TRUE(schedule(TKG, 8, 8, true).usesBoxFlow());
  EXPECT_TRUE(schedule(TKG, 1, 4, true, 4).usesBoxFlow());
  // Explicit settings win; modes without the Kalman tracker have no tracks to move.
  auto on = schedule(TKG, 1, 0, false);
  on.box_flow = "on";
  EXPECT_TRUE(on.usesBoxFlow());
  auto off = schedule(TKG, 8, 8, true);
  off.box_flow = "off";
  EXPECT_FALSE(off.usesBoxFlow());
  EXPECT_FALSE(schedule(DynamicMode::T, 8, 8, false).usesBoxFlow());
}

}  // namespace
}  // namespace tkgslam
