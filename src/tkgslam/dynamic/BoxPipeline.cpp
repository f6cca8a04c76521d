#include "tkgslam/dynamic/BoxPipeline.h"

#include <algorithm>
#include <chrono>

#include <fmt/format.h>

#include "tkgslam/common/Elapsed.h"
#include "tkgslam/common/Error.h"

namespace tkgslam::dynamic {

BoxPipeline::BoxPipeline(const DetectorParams& detector, const BoxTrackerParams& tracker,
                         const BoxScheduleParams& schedule)
    : schedule_(schedule), tracker_(tracker) {
  if (schedule_.detect_every < 1) throw InputError("dynamic.detect_every must be >= 1");
  if (schedule_.tiles < 1 || schedule_.tiles > 9) throw InputError("dynamic.detector_tiles must be in [1, 9]");
  if (schedule_.tiles > 1 && !schedule_.lookahead) throw InputError("dynamic.detector_tiles > 1 needs lookahead");
  const int period = schedule_.detect_every * schedule_.tiles;  // frames per detector run
  if (schedule_.latency < 0 || schedule_.latency > period) {
    throw InputError(schedule_.tiles == 1
                         ? fmt::format("dynamic.detector_latency must be in [0, detect_every = {}], got {}",
                                       schedule_.detect_every, schedule_.latency)
                         : fmt::format("dynamic.detector_latency must be in [0, detect_every x detector_tiles = {}], got {}",
                                       period, schedule_.latency));
  }
  if (schedule_.lookahead && !schedule_.use_kalman) throw InputError("dynamic.lookahead needs a Kalman mode (TK, TKG)");
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

void BoxPipeline::beginFrame(long index, const cv::Mat& bgr, const cv::Mat& depth_m, const cv::Mat& gray) {
  index_ = index;
  image_ = bgr.size();
  begin_timings_ = {};
  if (schedule_.use_kalman && schedule_.use_flow) {
    const auto tf = std::chrono::steady_clock::now();
    flow_frames_.emplace_back(index, flow_.prepare(gray.empty() ? bgr : gray, depth_m));
    // Kept: frame index - latency - 1 (before the oldest detection that can still be rewound to);
    // lookahead: from the last final frame on (the box tracker is there).
    const long keep_from = schedule_.lookahead ? final_through_ : index - schedule_.latency - 1;
    while (flow_frames_.front().first < keep_from) flow_frames_.pop_front();
    begin_timings_.tracker_ms += msSince(tf);
  }
  // A detection started L frames ago is due: it must be consumed before the next one starts
  // (one detection in flight at a time, so it never competes with itself for the cores).
  if (pending_ && schedule_.latency > 0 && index >= pending_->frame() + schedule_.latency) {
    if (schedule_.lookahead) {
      finalize(*pending_, begin_timings_);
    } else {
      consume(*pending_, index, image_, begin_timings_);
    }
    pending_.reset();
  }
  if (index % schedule_.detect_every != 0) return;
  // A frame waiting for its group is kept as a copy: the caller may reuse its buffer meanwhile.
  tile_frames_.emplace_back(index, schedule_.tiles > 1 ? bgr.clone() : bgr);
  if (int(tile_frames_.size()) < schedule_.tiles) return;
  launch();
  if (schedule_.lookahead && schedule_.latency == 0) {  // used on its own frame: wait for it
    finalize(*pending_, begin_timings_);
    pending_.reset();
  }
}

void BoxPipeline::launch() {
  Pending p;
  if (!schedule_.lookahead) p.tracker_before = tracker_;  // consume() rewinds to it
  std::vector<cv::Mat> images;
  for (auto& [f, bgr] : tile_frames_) {
    p.tiles.push_back(f);
    images.push_back(bgr);  // the task keeps its own references (cv::Mat is reference counted)
  }
  tile_frames_.clear();
  p.result = std::async(std::launch::async, [this, images = std::move(images)] {
    const auto t0 = std::chrono::steady_clock::now();
    auto dets = detector_->detectTiles(images);
    return Result(std::move(dets), msSince(t0));
  });
  pending_ = std::move(p);
}

std::vector<cv::Rect2f> BoxPipeline::followBack(const cv::Rect2f& box, long k, long first, cv::Size image) const {
  const cv::Rect2f frame_rect(0, 0, float(image.width), float(image.height));
  std::vector<cv::Rect2f> out;
  cv::Rect2f b = box;
  for (long f = k - 1; f >= first; --f) {
    const FlowFrame* from = flowFrame(f + 1);
    const FlowFrame* to = flowFrame(f);
    if (!from || !to) break;
    const auto moved = flow_.propagate(*from, *to, {b});
    if (!moved[0]) break;
    b = *moved[0];
    const cv::Rect2f clipped = b & frame_rect;
    if (clipped.area() < 0.005f * frame_rect.area()) break;  // walked out of the image
    out.push_back(clipped);
  }
  return out;
}

void BoxPipeline::predictThrough(long last, cv::Size image, std::vector<FrameBoxes>& out) {
  for (long f = final_through_ + 1; f <= last; ++f) {
    const auto moved = flowTo(f);
    out.emplace_back(f, tracker_.predictAll(image, moved ? &*moved : nullptr));
  }
  final_through_ = std::max(final_through_, last);
}

void BoxPipeline::finalize(Pending& p, BoxTimings& timings) {
  const auto tw = std::chrono::steady_clock::now();
  auto [per_tile, ms] = p.result.get();
  timings.wait_ms += msSince(tw);
  timings.detector_ms = ms;
  for (size_t j = 0; j < p.tiles.size(); ++j) finalizeThrough(p.tiles[j], per_tile[j], image_, timings);
}

void BoxPipeline::finalizeThrough(long frame, const std::vector<Detection>& detections, cv::Size image,
                                  BoxTimings& timings) {
  const auto tt = std::chrono::steady_clock::now();
  const long start = final_through_;  // the box tracker's frame
  std::vector<FrameBoxes> span;       // start + 1 .. frame - 1: forward boxes
  predictThrough(frame - 1, image, span);
  const auto moved = flowTo(frame);
  BoxTracker probe = tracker_;  // where the tracks would be without the detection
  const auto predicted = probe.predictAll(image, moved ? &*moved : nullptr);
  auto out = tracker_.update(detections, image, moved ? &*moved : nullptr);
  const cv::Rect2f frame_rect(0, 0, float(image.width), float(image.height));
  for (const auto& d : out) {
    if (d.predicted) continue;  // a missed detection: its forward boxes stand
    const auto q = std::find_if(predicted.begin(), predicted.end(),
                                [&d](const Detection& x) { return x.track_id == d.track_id; });
    if (q != predicted.end()) {
      // The prediction's error at the detection, spread linearly over the frames since `start`.
      for (auto& [f, boxes] : span) {
        const float w = float(f - start) / float(frame - start);
        for (auto& b : boxes) {
          if (b.track_id != d.track_id) continue;
          b.box.x += w * (d.box.x - q->box.x);
          b.box.y += w * (d.box.y - q->box.y);
          b.box.width += w * (d.box.width - q->box.width);
          b.box.height += w * (d.box.height - q->box.height);
          b.box &= frame_rect;
        }
      }
    } else {
      // First seen now: it was walking in before the detector caught it.
      const auto back = followBack(d.box, frame, start + 1, image);
      for (size_t j = 0; j < back.size(); ++j) {
        Detection b = d;
        b.box = back[j];
        b.predicted = true;
        span[span.size() - 1 - j].second.push_back(b);
      }
    }
  }
  for (auto& [f, boxes] : span) {
    boxes.erase(std::remove_if(boxes.begin(), boxes.end(), [](const Detection& b) { return b.box.area() <= 0; }),
                boxes.end());
    final_boxes_.emplace_back(f, std::move(boxes));
  }
  final_boxes_.emplace_back(frame, std::move(out));
  final_through_ = frame;
  timings.tracker_ms += msSince(tt);
}

std::vector<FrameBoxes> BoxPipeline::takeFinalBoxes(BoxTimings& timings) {
  timings = begin_timings_;
  return std::exchange(final_boxes_, {});
}

std::vector<FrameBoxes> BoxPipeline::flush(BoxTimings& timings) {
  timings = {};
  if (pending_) {
    finalize(*pending_, timings);
    pending_.reset();
  }
  if (!tile_frames_.empty()) {  // a group the sequence ended in: detect what there is
    launch();
    finalize(*pending_, timings);
    pending_.reset();
  }
  const auto tt = std::chrono::steady_clock::now();
  predictThrough(index_, image_, final_boxes_);
  timings.tracker_ms += msSince(tt);
  return std::exchange(final_boxes_, {});
}

std::vector<Detection> BoxPipeline::consume(Pending& p, long index, cv::Size image, BoxTimings& timings) {
  const auto tw = std::chrono::steady_clock::now();
  auto [per_tile, ms] = p.result.get();
  auto& detections = per_tile.front();
  timings.wait_ms += msSince(tw);
  timings.detector_ms = ms;
  const auto tt = std::chrono::steady_clock::now();
  std::vector<Detection> out;
  if (schedule_.use_kalman) {
    // Rewind to the detection's frame, update there, predict the frames since (none when the
    // detection is used on its own frame).
    tracker_ = std::move(p.tracker_before);
    auto moved = flowTo(p.frame());
    out = tracker_.update(detections, image, moved ? &*moved : nullptr);
    late_boxes_.clear();
    if (p.frame() < index) late_boxes_.emplace_back(p.frame(), out);
    for (long f = p.frame() + 1; f < index; ++f) {
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
  const bool synchronous = pending_ && pending_->frame() == index_ && (schedule_.latency == 0 || index_ == 0);
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
