// The detection schedule: synchronous first frame, fixed latency afterwards, Kalman prediction in
// between, and the same boxes whatever the thread timing (the result only depends on indices).
#include <map>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

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

// The left man on bus.jpg (pixels of the photo, read off by eye), the picture shifted right by dx.
cv::Rect2f kLeftManAt(float dx) { return cv::Rect2f(50 + dx, 398, 158, 500); }

/// `photo` shifted right by dx pixels (a camera pan); what comes into view is `border`.
cv::Mat shifted(const cv::Mat& photo, double dx, int border = cv::BORDER_REPLICATE) {
  cv::Mat out;
  const cv::Mat m = (cv::Mat_<double>(2, 3) << 1, 0, dx, 0, 1, 0);
  cv::warpAffine(photo, out, m, photo.size(), cv::INTER_LINEAR, border);
  return out;
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

TEST(BoxPipeline, BetweenLateDetectionsBoxesFollowTheImageByOpticalFlow) {
  TKGSLAM_REQUIRE_SHARED();
  const cv::Mat bus = cv::imread((test::sharedDir() / "datasets/people/bus.jpg").string());
  ASSERT_FALSE(bus.empty());
  // The camera pans, the picture moving 6 px right per frame, and stops after frame 4.
  auto frame = [&](int i) { return shifted(bus, 6.0 * std::min(i, 4)); };
  auto run = [&](bool flow) {
    dynamic::BoxPipeline pipeline(detectorParams(), {}, {/*detect_every=*/4, /*latency=*/4, true, flow});
    std::vector<std::vector<dynamic::Detection>> boxes;
    for (int i = 0; i < 10; ++i) {
      const cv::Mat image = frame(i);
      pipeline.beginFrame(i, image);
      dynamic::BoxTimings t;
      boxes.push_back(pipeline.frameBoxes(image.size(), t));
    }
    return boxes;
  };
  const auto with_flow = run(true), without = run(false);
  // Boxes of frame 0 away from the border, and where they are on frame 3 (no detection has
  // arrived since frame 0: the one started on frame 4 is used on frame 8) and on frame 9 (the
  // tracker was rewound to frame 4, updated, and the flow of frames 5-8 replayed: the boxes
  // stopped with the picture instead of going on at the old velocity).
  const cv::Rect2f inner(2, 2, float(bus.cols) - 60, float(bus.rows) - 4);
  int checked = 0;
  for (size_t b = 0; b < with_flow[0].size(); ++b) {
    const cv::Rect2f r0 = with_flow[0][b].box;
    if ((r0 & inner) != r0) continue;
    const cv::Rect2f expected = r0 + cv::Point2f(18, 0);
    ASSERT_LT(b, with_flow[3].size());
    EXPECT_GT(dynamic::iou(with_flow[3][b].box, expected), 0.9f) << with_flow[3][b].box << " vs " << expected;
    // Without flow a new track has no velocity: its box stays where it was detected.
    EXPECT_GT(dynamic::iou(without[3][b].box, r0), 0.95f);
    const cv::Rect2f at9 = r0 + cv::Point2f(24, 0);
    float best = 0;
    for (const auto& d : with_flow[9]) best = std::max(best, dynamic::iou(d.box, at9));
    EXPECT_GT(best, 0.85f) << "frame 9, expected near " << at9;
    ++checked;
  }
  EXPECT_GE(checked, 2);
}

TEST(BoxPipeline, LookaheadBoxesPeopleBeforeTheDetectorFirstSeesThem) {
  TKGSLAM_REQUIRE_SHARED();
  const cv::Mat bus = cv::imread((test::sharedDir() / "datasets/people/bus.jpg").string());
  ASSERT_FALSE(bus.empty());
  // The camera pans left to right: the picture enters from the left, 50 px per frame, so the man on
  // the left of bus.jpg walks into view from the border (black: nothing there yet) and stops at 4.
  const auto shift = [](int i) { return -200.0f + 50.0f * std::min(i, 4); };
  auto frame = [&](int i) { return shifted(bus, shift(i), cv::BORDER_CONSTANT); };
  dynamic::BoxPipeline pipeline(detectorParams(), {}, {/*detect_every=*/4, /*latency=*/4, true, true, /*lookahead=*/true});
  std::map<long, std::vector<dynamic::Detection>> boxes;
  dynamic::BoxTimings t;
  for (int i = 0; i < 10; ++i) {
    const cv::Mat image = frame(i);
    pipeline.beginFrame(i, image);
    for (auto& [f, b] : pipeline.takeFinalBoxes(t)) boxes[f] = std::move(b);
    // Frames are final only once the detection after them has arrived: on frame 4 (frame 0's),
    // frame 8 (frames 1-4, detected on frame 4). None may come twice or out of order.
    EXPECT_EQ(long(boxes.size()), i < 4 ? 0 : i < 8 ? 1 : 5) << "frame " << i;
  }
  for (auto& [f, b] : pipeline.flush(t)) boxes[f] = std::move(b);
  ASSERT_EQ(boxes.size(), 10u);
  // People detected on frame 4 but on no box of frame 0: they walked in meanwhile. Followed back
  // by optical flow, they have boxes on frames 1-3, where they were (frame 4's box shifted back).
  const cv::Rect2f image_rect(0, 0, float(bus.cols), float(bus.rows));
  int entered = 0, checked = 0;
  for (const auto& d : boxes[4]) {
    if (d.predicted) continue;
    bool seen_at_0 = false;
    for (const auto& b0 : boxes[0]) seen_at_0 |= dynamic::iou(b0.box, d.box - cv::Point2f(200, 0)) > 0.3f;
    if (seen_at_0) continue;
    ++entered;
    for (int f = 1; f <= 3; ++f) {
      const cv::Rect2f expected = (d.box - cv::Point2f(50.0f * float(4 - f), 0)) & image_rect;
      if (expected.area() < 0.02f * image_rect.area()) continue;
      float best = 0;
      for (const auto& b : boxes[f]) best = std::max(best, dynamic::iou(b.box, expected));
      EXPECT_GT(best, 0.7f) << "frame " << f << ": expected a box near " << expected;
      ++checked;
    }
  }
  EXPECT_GE(entered, 1) << "the pan should bring someone new into view";
  EXPECT_GE(checked, 2);
}

TEST(BoxPipeline, TiledRunsDetectEachFrameOfTheGroup) {
  TKGSLAM_REQUIRE_SHARED();
  const cv::Mat bus = cv::imread((test::sharedDir() / "datasets/people/bus.jpg").string());
  ASSERT_FALSE(bus.empty());
  // The picture pans 20 px per frame; frames 0, 2, 4, 6 are detected in one run started on frame 6
  // (tiles 4, every 2nd frame) and used 2 frames later.
  auto frame = [&](int i) { return shifted(bus, 20.0 * i); };
  dynamic::BoxPipeline pipeline(detectorParams(), {},
                                {/*detect_every=*/2, /*latency=*/2, true, true, /*lookahead=*/true, /*tiles=*/4});
  std::map<long, std::vector<dynamic::Detection>> boxes;
  dynamic::BoxTimings t;
  int runs = 0;
  for (int i = 0; i < 11; ++i) {
    const cv::Mat image = frame(i);
    pipeline.beginFrame(i, image);
    for (auto& [f, b] : pipeline.takeFinalBoxes(t)) boxes[f] = std::move(b);
    runs += t.detector_ms >= 0;
    // Nothing is final before the first run arrives (frame 8); then frames 0-6 at once.
    EXPECT_EQ(long(boxes.size()), i < 8 ? 0 : 7) << "frame " << i;
  }
  EXPECT_EQ(runs, 1);
  for (auto& [f, b] : pipeline.flush(t)) boxes[f] = std::move(b);  // frames 8 and 10 detected here
  ASSERT_EQ(boxes.size(), 11u);
  // Each detected frame has the left man as a detection (not a prediction) where that frame
  // shows him: a tile given to the wrong frame would be off by 40 px or more.
  for (int f = 0; f <= 10; f += 2) {
    const cv::Rect2f expected = kLeftManAt(20.0f * float(f));
    float best = 0;
    for (const auto& d : boxes[f]) {
      if (!d.predicted && d.class_id == 0) best = std::max(best, dynamic::iou(d.box, expected));
    }
    EXPECT_GT(best, 0.75f) << "frame " << f;
  }
  EXPECT_THROW(dynamic::BoxPipeline(detectorParams(), {}, {2, 2, true, true, /*lookahead=*/false, 4}), InputError);
  EXPECT_THROW(dynamic::BoxPipeline(detectorParams(), {}, {2, 9, true, true, true, 4}), InputError);
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
