#pragma once
// SORT-style multi-box tracker with the paper's missed-detection rule (§3.2):
// each frame, every track is predicted; detections are assigned to predictions by the Hungarian
// method on 1 - IoU (pairs below the IoU gate are rejected); matched tracks are updated,
// unmatched detections start tracks, tracks unmatched for more than max_age frames die.
// Missed detections: if the previous frame output more boxes than the detector found now, and
// more tracks are alive than detections, the unmatched tracks' predicted boxes are added to the
// output (marked `predicted`). "Previous frame" counts its output boxes, so a detection that
// vanishes for several frames stays filled in until its track dies.
#include <vector>

#include "tkgslam/dynamic/BoxKalmanFilter.h"
#include "tkgslam/dynamic/Detection.h"

namespace tkgslam::dynamic {

struct BoxTrackerParams {
  KalmanParams kalman;
  float iou_gate = 0.3f;  ///< minimum IoU of an assignment
  int max_age = 3;        ///< frames a track survives without a matching detection
};

class BoxTracker {
 public:
  explicit BoxTracker(const BoxTrackerParams& params = {}) : params_(params) {}

  /// Processes one frame's detections; returns them (with track ids) plus predicted boxes for
  /// missed detections, clipped to the image when a size is given.
  std::vector<Detection> update(const std::vector<Detection>& detections, cv::Size image = {});

  /// For frames on which the detector did not run: every live track's prediction, marked
  /// `predicted`, without counting it as a miss.
  std::vector<Detection> predictAll(cv::Size image = {});

  int liveTracks() const { return int(tracks_.size()); }

 private:
  struct Track {
    int id;
    int class_id;
    float score;
    BoxKalmanFilter kf;
    int misses = 0;  ///< consecutive frames without a matched detection
    cv::Rect2f predicted;
  };
  BoxTrackerParams params_;
  std::vector<Track> tracks_;
  int next_id_ = 0;
  int previous_output_ = 0;
};

}  // namespace tkgslam::dynamic
