#include "tkgslam/dynamic/BoxTracker.h"

#include <algorithm>
#include <cmath>

#include "tkgslam/dynamic/Hungarian.h"

namespace tkgslam::dynamic {

namespace {
/// Distance of the two boxes' centres in units of b's size sqrt(w h).
float centreDistance(const cv::Rect2f& a, const cv::Rect2f& b) {
  const float dx = (a.x + 0.5f * a.width) - (b.x + 0.5f * b.width);
  const float dy = (a.y + 0.5f * a.height) - (b.y + 0.5f * b.height);
  return std::hypot(dx, dy) / std::max(std::sqrt(b.area()), 1.0f);
}
}  // namespace

bool BoxTracker::gateAccepts(const cv::Rect2f& det, const Track& t) const {
  if (iou(det, t.predicted) >= params_.iou_gate) return true;
  if (params_.centre_gate <= 0) return false;
  // Far-apart boxes of very different size are different objects, however long the gap.
  const float ratio = det.area() / std::max(t.predicted.area(), 1.0f);
  if (ratio < 0.25f || ratio > 4.0f) return false;
  const float gate = std::min(params_.centre_gate * float(t.frames_since_update), params_.centre_gate_max);
  return centreDistance(det, t.predicted) <= gate;
}

void BoxTracker::predictTracks(const Moved* moved) {
  for (size_t i = 0; i < tracks_.size(); ++i) {
    Track& t = tracks_[i];
    t.predicted = t.kf.predict();
    t.frames_since_update++;
    if (moved && i < moved->size() && (*moved)[i]) {
      t.kf.follow(*(*moved)[i]);
      t.predicted = t.kf.box();
    }
  }
}

void BoxTracker::addPrediction(const Track& t, cv::Size image, std::vector<Detection>& out) {
  Detection p;
  p.box = t.predicted;
  if (image.area() > 0) p.box &= cv::Rect2f(0, 0, float(image.width), float(image.height));
  p.class_id = t.class_id;
  p.score = t.score;
  p.predicted = true;
  p.track_id = t.id;
  if (p.box.area() > 0) out.push_back(p);
}

std::vector<cv::Rect2f> BoxTracker::lastBoxes() const {
  std::vector<cv::Rect2f> boxes;
  for (const auto& t : tracks_) boxes.push_back(t.kf.box());
  return boxes;
}

std::vector<Detection> BoxTracker::update(const std::vector<Detection>& detections, cv::Size image,
                                          const Moved* moved) {
  predictTracks(moved);

  std::vector<int> track_of(detections.size(), -1);
  std::vector<char> track_matched(tracks_.size(), 0);
  if (!detections.empty() && !tracks_.empty()) {
    std::vector<std::vector<double>> cost(detections.size(), std::vector<double>(tracks_.size()));
    for (size_t d = 0; d < detections.size(); ++d) {
      for (size_t t = 0; t < tracks_.size(); ++t) {
        // Overlap first; among boxes that do not overlap, the nearer centre.
        const cv::Rect2f& p = tracks_[t].predicted;
        cost[d][t] = 1.0 - iou(detections[d].box, p) + 0.5 * std::min(centreDistance(detections[d].box, p), 4.0f);
      }
    }
    const auto assignment = solveAssignment(cost);
    for (size_t d = 0; d < detections.size(); ++d) {
      const int t = assignment[d];
      if (t < 0 || !gateAccepts(detections[d].box, tracks_[t])) continue;
      track_of[d] = t;
      track_matched[t] = 1;
    }
  }

  std::vector<Detection> out;
  for (size_t d = 0; d < detections.size(); ++d) {
    Detection det = detections[d];
    if (track_of[d] >= 0) {
      Track& t = tracks_[track_of[d]];
      t.kf.update(det.box);
      t.misses = 0;
      t.frames_since_update = 0;
      t.class_id = det.class_id;
      t.score = det.score;
      det.track_id = t.id;
    } else {
      tracks_.push_back({next_id_++, det.class_id, det.score, BoxKalmanFilter(det.box, params_.kalman), 0, 0, det.box});
      track_matched.push_back(1);
      det.track_id = tracks_.back().id;
    }
    out.push_back(det);
  }

  // Missed-detection rule of the paper.
  const int n_det = int(detections.size());
  const bool fill = previous_output_ > n_det && int(tracks_.size()) > n_det;
  for (size_t t = 0; t < tracks_.size(); ++t) {
    if (track_matched[t]) continue;
    tracks_[t].misses++;
    if (fill && tracks_[t].misses <= params_.max_age) addPrediction(tracks_[t], image, out);
  }
  std::vector<Track> alive;
  for (auto& t : tracks_) {
    if (t.misses <= params_.max_age) alive.push_back(std::move(t));
  }
  tracks_ = std::move(alive);
  previous_output_ = int(out.size());
  return out;
}

std::vector<Detection> BoxTracker::predictAll(cv::Size image, const Moved* moved) {
  predictTracks(moved);
  std::vector<Detection> out;
  for (const auto& t : tracks_) addPrediction(t, image, out);
  previous_output_ = int(out.size());
  return out;
}

}  // namespace tkgslam::dynamic
