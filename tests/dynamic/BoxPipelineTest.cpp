// The detection schedule: synchronous first frame, fixed latency afterwards, Kalman prediction in
// between, and the same boxes whatever the thread timing (the result only depends on indices).
#include <opencv2/imgcodecs.hpp>

#include <gtest/gtest.h>

#include "TestSupport.h"
#include "tkgslam/common/Error.h"
#include "tkgslam/dynamic/BoxPipeline.h"

namespace tkgslam {
namespace {

dynamic::DetectorParams detectorParams() {
  dynamic::DetectorParams p;
  p.model = test::yoloModel();
  return p;
}

struct FrameOutput {
  std::vector<dynamic::Detection> boxes;
  dynamic::BoxTimings timings;
};

std::vector<FrameOutput> runFrames(dynamic::BoxPipeline& pipeline, const cv::Mat& image, int frames) {
  std::vector<FrameOutput> out;
  for (int i = 0; i < frames; ++i) {
    pipeline.beginFrame(i, image);
    FrameOutput f;
    f.boxes = pipeline.frameBoxes(image.size(), f.timings);
    out.push_back(std::move(f));
  }
  return out;
}

TEST(BoxPipeline, AsynchronousScheduleUsesEachDetectionLatencyFramesLater) {
  TKGSLAM_REQUIRE_SHARED();
  const cv::Mat bus = cv::imread((test::sharedDir() / "datasets/people/bus.jpg").string());
  ASSERT_FALSE(bus.empty());
  dynamic::BoxPipeline pipeline(detectorParams(), {}, {/*detect_every=*/3, /*latency=*/3, /*use_kalman=*/true});
  const auto frames = runFrames(pipeline, bus, 8);
  // Frame 0 is detected synchronously: real detector boxes, 4 persons + the bus on bus.jpg.
  EXPECT_GE(frames[0].timings.detector_ms, 0);
  ASSERT_GE(frames[0].boxes.size(), 4u);
  EXPECT_FALSE(frames[0].boxes[0].predicted);
  // The detection started on frame 3 is consumed on frame 6, not before; nothing else finishes.
  for (int i : {1, 2, 3, 4, 5, 7}) EXPECT_LT(frames[i].timings.detector_ms, 0) << "frame " << i;
  EXPECT_GE(frames[6].timings.detector_ms, 0);
  // In between, every box is the Kalman prediction of a live track (a still image: they stay put).
  for (int i = 1; i < 8; ++i) {
    ASSERT_EQ(frames[i].boxes.size(), frames[0].boxes.size()) << "frame " << i;
    for (size_t b = 0; b < frames[i].boxes.size(); ++b) {
      EXPECT_TRUE(frames[i].boxes[b].predicted);
      EXPECT_GT(dynamic::iou(frames[i].boxes[b].box, frames[0].boxes[b].box), 0.9f) << "frame " << i;
    }
  }
  // The schedule depends only on frame indices: a second pipeline gives identical boxes.
  dynamic::BoxPipeline again(detectorParams(), {}, {3, 3, true});
  const auto repeat = runFrames(again, bus, 8);
  for (int i = 0; i < 8; ++i) {
    ASSERT_EQ(repeat[i].boxes.size(), frames[i].boxes.size());
    for (size_t b = 0; b < frames[i].boxes.size(); ++b) EXPECT_EQ(repeat[i].boxes[b].box, frames[i].boxes[b].box);
  }
}

TEST(BoxPipeline, WithoutKalmanTheLastDetectionIsReused) {
  TKGSLAM_REQUIRE_SHARED();
  const cv::Mat bus = cv::imread((test::sharedDir() / "datasets/people/bus.jpg").string());
  dynamic::BoxPipeline pipeline(detectorParams(), {}, {2, 0, false});
  const auto frames = runFrames(pipeline, bus, 3);
  EXPECT_GE(frames[0].timings.detector_ms, 0);
  EXPECT_LT(frames[1].timings.detector_ms, 0);
  EXPECT_GE(frames[2].timings.detector_ms, 0);  // latency 0: detected and used on the same frame
  ASSERT_EQ(frames[1].boxes.size(), frames[0].boxes.size());
  EXPECT_FALSE(frames[1].boxes[0].predicted);
}

TEST(BoxPipeline, LatencyLongerThanTheDetectionPeriodIsAnError) {
  TKGSLAM_REQUIRE_SHARED();
  EXPECT_THROW(dynamic::BoxPipeline(detectorParams(), {}, {2, 3, true}), InputError);
  EXPECT_THROW(dynamic::BoxPipeline(detectorParams(), {}, {0, 0, true}), InputError);
}

}  // namespace
}  // namespace tkgslam
