#include "tkgslam/dynamic/BoxPipeline.h"

#include <chrono>

#include <fmt/format.h>

#include "tkgslam/common/Elapsed.h"
#include "tkgslam/common/Error.h"

namespace tkgslam::dynamic {

BoxPipeline::BoxPipeline(const DetectorParams& detector, const BoxTrackerParams& tracker,
                         const BoxScheduleParams& schedule)
    : schedule_(schedule), tracker_(tracker) {
  if (schedule_.detect_every < 1) throw InputError("dynamic.detect_every must be >= 1");
  if (schedule_.latency < 0 || schedule_.latency > schedule_.detect_every) {
    throw InputError(fmt::format("dynamic.detector_latency must be in [0, detect_every = {}], got {}",
                                 schedule_.detect_every, schedule_.latency));
  }
  detector_ = std::make_unique<YoloDetector>(detector);
}

BoxPipeline::~BoxPipeline() {
  if (pending_ && pending_->result.valid()) pending_->result.wait();
}

const FlowFrame* BoxPipeline::flowFrame(long frame) const {
  for (const auto& [f, pyramid] : flow_frames_) {
    if (f == frame) return &pyramid;
  }
  return nullptr;
}

std::optional<BoxTracker::Moved> BoxPipeline::flowTo(long frame) const {
  const FlowFrame* from = flowFrame(frame - 1);
  const FlowFrame* to = flowFrame(frame);
  if (!from || !to) return std::nullopt;
  return flow_.propagate(*from, *to, tracker_.lastBoxes());
}

void BoxPipeline::beginFrame(long index, const cv::Mat& bgr, const cv::Mat& depth_m) {
  index_ = index;
  begin_timings_ = {};
  if (schedule_.use_kalman && schedule_.use_flow) {
    const auto tf = std::chrono::steady_clock::now();
    flow_frames_.emplace_back(index, flow_.prepare(bgr, depth_m));
    // Kept: frame index - latency - 1 (before the oldest detection that can still be rewound to).
    while (flow_frames_.front().first < index - schedule_.latency - 1) flow_frames_.pop_front();
    begin_timings_.tracker_ms += msSince(tf);
  }
  // A detection started L frames ago is due: it must be consumed before the next one starts
  // (one detection in flight at a time, so it never competes with itself for the cores).
  if (pending_ && schedule_.latency > 0 && index >= pending_->frame + schedule_.latency) {
    consume(*pending_, index, bgr.size(), begin_timings_);
    pending_.reset();
  }
  if (index % schedule_.detect_every != 0) return;
  Pending p;
  p.frame = index;
  p.tracker_before = tracker_;
  // The task keeps its own reference to the image (cv::Mat is reference counted).
  p.result = std::async(std::launch::async, [this, image = bgr] {
    const auto t0 = std::chrono::steady_clock::now();
    auto dets = detector_->detect(image);
    return Result(std::move(dets), msSince(t0));
  });
  pending_ = std::move(p);
}

std::vector<Detection> BoxPipeline::consume(Pending& p, long index, cv::Size image, BoxTimings& timings) {
  const auto tw = std::chrono::steady_clock::now();
  auto [detections, ms] = p.result.get();
  timings.wait_ms += msSince(tw);
  timings.detector_ms = ms;
  const auto tt = std::chrono::steady_clock::now();
  std::vector<Detection> out;
  if (schedule_.use_kalman) {
    // Rewind to the detection's frame, update there, predict the frames since (none when the
    // detection is used on its own frame).
    tracker_ = std::move(p.tracker_before);
    auto moved = flowTo(p.frame);
    out = tracker_.update(detections, image, moved ? &*moved : nullptr);
    late_boxes_.clear();
    if (p.frame < index) late_boxes_.emplace_back(p.frame, out);
    for (long f = p.frame + 1; f < index; ++f) {
      moved = flowTo(f);
      late_boxes_.emplace_back(f, tracker_.predictAll(image, moved ? &*moved : nullptr));
    }
  } else {
    last_detections_ = std::move(detections);
    out = last_detections_;
  }
  timings.tracker_ms += msSince(tt);
  return out;
}

std::vector<Detection> BoxPipeline::frameBoxes(cv::Size image, BoxTimings& timings) {
  timings = begin_timings_;
  const bool synchronous = pending_ && pending_->frame == index_ && (schedule_.latency == 0 || index_ == 0);
  if (synchronous) {
    auto out = consume(*pending_, index_, image, timings);
    pending_.reset();
    return out;
  }
  if (!schedule_.use_kalman) return last_detections_;  // frames between detections reuse the last boxes
  const auto tt = std::chrono::steady_clock::now();
  const auto moved = flowTo(index_);
  auto out = tracker_.predictAll(image, moved ? &*moved : nullptr);
  timings.tracker_ms += msSince(tt);
  return out;
}

}  // namespace tkgslam::dynamic
