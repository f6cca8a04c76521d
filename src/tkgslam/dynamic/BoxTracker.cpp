#include "tkgslam/dynamic/BoxTracker.h"

#include "tkgslam/dynamic/Hungarian.h"

namespace tkgslam::dynamic {

std::vector<Detection> BoxTracker::update(const std::vector<Detection>& detections, cv::Size image) {
  for (auto& t : tracks_) t.predicted = t.kf.predict();

  std::vector<int> track_of(detections.size(), -1);
  std::vector<char> track_matched(tracks_.size(), 0);
  if (!detections.empty() && !tracks_.empty()) {
    std::vector<std::vector<double>> cost(detections.size(), std::vector<double>(tracks_.size()));
    for (size_t d = 0; d < detections.size(); ++d) {
      for (size_t t = 0; t < tracks_.size(); ++t) cost[d][t] = 1.0 - iou(detections[d].box, tracks_[t].predicted);
    }
    const auto assignment = solveAssignment(cost);
    for (size_t d = 0; d < detections.size(); ++d) {
      const int t = assignment[d];
      if (t < 0 || 1.0 - cost[d][t] < params_.iou_gate) continue;
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
      t.class_id = det.class_id;
      t.score = det.score;
      det.track_id = t.id;
    } else {
      tracks_.push_back({next_id_++, det.class_id, det.score, BoxKalmanFilter(det.box, params_.kalman), 0, det.box});
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
    if (fill && tracks_[t].misses <= params_.max_age) {
      Detection p;
      p.box = tracks_[t].predicted;
      if (image.area() > 0) p.box &= cv::Rect2f(0, 0, float(image.width), float(image.height));
      p.class_id = tracks_[t].class_id;
      p.score = tracks_[t].score;
      p.predicted = true;
      p.track_id = tracks_[t].id;
      if (p.box.area() > 0) out.push_back(p);
    }
  }
  std::vector<Track> alive;
  for (auto& t : tracks_) {
    if (t.misses <= params_.max_age) alive.push_back(std::move(t));
  }
  tracks_ = std::move(alive);
  previous_output_ = int(out.size());
  return out;
}

std::vector<Detection> BoxTracker::predictAll(cv::Size image) {
  std::vector<Detection> out;
  for (auto& t : tracks_) {
    t.predicted = t.kf.predict();
    Detection p;
    p.box = t.predicted;
    if (image.area() > 0) p.box &= cv::Rect2f(0, 0, float(image.width), float(image.height));
    p.class_id = t.class_id;
    p.score = t.score;
    p.predicted = true;
    p.track_id = t.id;
    if (p.box.area() > 0) out.push_back(p);
  }
  previous_output_ = int(out.size());
  return out;
}

}  // namespace tkgslam::dynamic
