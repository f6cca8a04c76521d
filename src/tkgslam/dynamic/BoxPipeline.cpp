#include "tkgslam/dynamic/BoxPipeline.h"

#include <algorithm>
#include <chrono>
#include <iterator>
#include <stdexcept>

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

const FlowFrame* BoxPipeline::flowFrame(const FlowFrames& frames, long frame) {
  for (const auto& [f, pyramid] : frames) {
    if (f == frame) return &pyramid;
  }
  return nullptr;
}

std::optional<BoxTracker::Moved> BoxPipeline::flowTo(const FlowFrames& frames, const BoxTracker& tracker,
                                                     long frame) const {
  const FlowFrame* from = flowFrame(frames, frame - 1);
  const FlowFrame* to = flowFrame(frames, frame);
  if (!from || !to) return std::nullopt;
  return flow_.propagate(*from, *to, tracker.lastBoxes());
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
  if (pending_) throw std::logic_error("BoxPipeline: a detector run is still pending");
  Pending p;
  if (!schedule_.lookahead) p.tracker_before = tracker_;  // consume() rewinds to it
  std::vector<cv::Mat> images;
  for (auto& [f, bgr] : tile_frames_) {
    p.tiles.push_back(f);
    images.push_back(bgr);  // the task keeps its own references (cv::Mat is reference counted)
  }
  tile_frames_.clear();
  // Lookahead: the run finalizes its frames itself, from a copy of the state (the previous run
  // is final by now) and of the pyramids it needs (cv::Mat headers; the caller may drop its own).
  std::optional<Lookahead> state;
  FlowFrames frames;
  if (schedule_.lookahead) {
    state = Lookahead{tracker_, final_through_, {}, 0.0};
    frames = flow_frames_;  // beginFrame keeps exactly those from final_through_ on
  }
  p.result = std::async(std::launch::async, [this, images = std::move(images), tiles = p.tiles,
                                             state = std::move(state), frames = std::move(frames),
                                             image = image_]() mutable {
    const auto t0 = std::chrono::steady_clock::now();
    Result r;
    r.per_tile = detector_->detectTiles(images);
    r.detector_ms = msSince(t0);
    if (state) {
      const auto tt = std::chrono::steady_clock::now();
      for (size_t j = 0; j < tiles.size(); ++j) finalizeThrough(*state, frames, tiles[j], r.per_tile[j], image);
      state->tracker_ms = msSince(tt);
      r.lookahead = std::move(state);
    }
    return r;
  });
  pending_ = std::move(p);
}

std::vector<cv::Rect2f> BoxPipeline::followBack(const FlowFrames& frames, const cv::Rect2f& box, long k, long first,
                                                cv::Size image) const {
  const cv::Rect2f frame_rect(0, 0, float(image.width), float(image.height));
  std::vector<cv::Rect2f> out;
  cv::Rect2f b = box;
  for (long f = k - 1; f >= first; --f) {
    const FlowFrame* from = flowFrame(frames, f + 1);
    const FlowFrame* to = flowFrame(frames, f);
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

void BoxPipeline::predictThrough(Lookahead& state, const FlowFrames& frames, long last, cv::Size image,
                                 std::vector<FrameBoxes>& out) const {
  for (long f = state.through + 1; f <= last; ++f) {
    const auto moved = flowTo(frames, state.tracker, f);
    out.emplace_back(f, state.tracker.predictAll(image, moved ? &*moved : nullptr));
  }
  state.through = std::max(state.through, last);
}

void BoxPipeline::finalize(Pending& p, BoxTimings& timings) {
  const auto tw = std::chrono::steady_clock::now();
  Result r = p.result.get();
  timings.wait_ms += msSince(tw);
  timings.detector_ms = r.detector_ms;
  Lookahead& state = *r.lookahead;
  timings.tracker_ms += state.tracker_ms;
  tracker_ = std::move(state.tracker);
  final_through_ = state.through;
  std::move(state.boxes.begin(), state.boxes.end(), std::back_inserter(final_boxes_));
}

void BoxPipeline::finalizeThrough(Lookahead& state, const FlowFrames& frames, long frame,
                                  const std::vector<Detection>& detections, cv::Size image) const {
  const long start = state.through;  // the box tracker's frame
  std::vector<FrameBoxes> span;      // start + 1 .. frame - 1: forward boxes
  predictThrough(state, frames, frame - 1, image, span);
  const auto moved = flowTo(frames, state.tracker, frame);
  BoxTracker probe = state.tracker;  // where the tracks would be without the detection
  const auto predicted = probe.predictAll(image, moved ? &*moved : nullptr);
  auto out = state.tracker.update(detections, image, moved ? &*moved : nullptr);
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
      const auto back = followBack(frames, d.box, frame, start + 1, image);
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
    state.boxes.emplace_back(f, std::move(boxes));
  }
  state.boxes.emplace_back(frame, std::move(out));
  state.through = frame;
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
  Lookahead state{std::move(tracker_), final_through_, {}, 0.0};
  predictThrough(state, flow_frames_, index_, image_, final_boxes_);
  tracker_ = std::move(state.tracker);
  final_through_ = state.through;
  timings.tracker_ms += msSince(tt);
  return std::exchange(final_boxes_, {});
}

std::vector<Detection> BoxPipeline::consume(Pending& p, long index, cv::Size image, BoxTimings& timings) {
  const auto tw = std::chrono::steady_clock::now();
  Result r = p.result.get();
  auto& detections = r.per_tile.front();
  timings.wait_ms += msSince(tw);
  timings.detector_ms = r.detector_ms;
  const auto tt = std::chrono::steady_clock::now();
  std::vector<Detection> out;
  if (schedule_.use_kalman) {
    // Rewind to the detection's frame, update there, predict the frames since (none when the
    // detection is used on its own frame).
    tracker_ = std::move(p.tracker_before);
    auto moved = flowTo(flow_frames_, tracker_, p.frame());
    out = tracker_.update(detections, image, moved ? &*moved : nullptr);
    late_boxes_.clear();
    if (p.frame() < index) late_boxes_.emplace_back(p.frame(), out);
    for (long f = p.frame() + 1; f < index; ++f) {
      moved = flowTo(flow_frames_, tracker_, f);
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
  const auto moved = flowTo(flow_frames_, tracker_, index_);
  auto out = tracker_.predictAll(image, moved ? &*moved : nullptr);
  timings.tracker_ms += msSince(tt);
  return out;
}

}  // namespace tkgslam::dynamic
