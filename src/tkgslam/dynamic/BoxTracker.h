#pragma once
// SORT-style multi-box tracker with the paper's missed-detection rule (§3.2):
// each frame, every track is predicted; detections are assigned to predictions by the Hungarian
// method on 1 - IoU plus the centre distance; a pair is accepted when its IoU passes the IoU gate
// or, failing that, its centre lies within centre_gate box sizes per frame since the track's last
// detection (when the detector runs every N-th frame, a fast person moves a whole box width
// between runs and a new track has no velocity yet: IoU alone would start a new track each run).
// Matched tracks are updated, unmatched detections start tracks, tracks unmatched by more than
// max_age detector runs die.
// Missed detections: if the previous frame output more boxes than the detector found now, and
// more tracks are alive than detections, the unmatched tracks' predicted boxes are added to the
// output (marked `predicted`). "Previous frame" counts its output boxes, so a detection that
// vanishes for several frames stays filled in until its track dies.
#include <optional>
#include <vector>

#include "tkgslam/dynamic/BoxKalmanFilter.h"
#include "tkgslam/dynamic/Detection.h"

namespace tkgslam::dynamic {

struct BoxTrackerParams {
  KalmanParams kalman;
  float iou_gate = 0.3f;  ///< minimum IoU of an assignment (or the centre gate below)
  /// Centre distance allowed per frame since the track's last detection, in units of the
  /// predicted box's size sqrt(w h); capped at centre_gate_max. 0 = IoU gate only.
  float centre_gate = 0.15f;
  float centre_gate_max = 1.5f;
  int max_age = 3;        ///< detector runs a track survives without a matching detection
};

class BoxTracker {
 public:
  /// Boxes of the live tracks measured on the new frame by other means than the detector (optical
  /// flow), in the order of lastBoxes(); nullopt where there is no measurement.
  using Moved = std::vector<std::optional<cv::Rect2f>>;

  explicit BoxTracker(const BoxTrackerParams& params = {}) : params_(params) {}

  /// Processes one frame's detections; returns them (with track ids) plus predicted boxes for
  /// missed detections, clipped to the image when a size is given. `moved` (optional) corrects
  /// the tracks' predictions before the detections are assigned to them.
  std::vector<Detection> update(const std::vector<Detection>& detections, cv::Size image = {},
                                const Moved* moved = nullptr);

  /// For frames on which the detector did not run: every live track's prediction (corrected by
  /// `moved` where given), marked `predicted`, without counting it as a miss.
  std::vector<Detection> predictAll(cv::Size image = {}, const Moved* moved = nullptr);

  /// Each live track's box on the last processed frame (unclipped), in track order.
  std::vector<cv::Rect2f> lastBoxes() const;

  int liveTracks() const { return int(tracks_.size()); }

 private:
  struct Track {
    int id;
    int class_id;
    float score;
    BoxKalmanFilter kf;
    int misses = 0;  ///< consecutive detector runs without a matched detection
    int frames_since_update = 0;  ///< predictions since the last matched detection
    cv::Rect2f predicted;
  };
  /// Predicts every track one frame, fused with its moved box where there is one.
  void predictTracks(const Moved* moved);
  /// Appends t's predicted box (clipped to the image) as a `predicted` detection, if not empty.
  static void addPrediction(const Track& t, cv::Size image, std::vector<Detection>& out);
  /// Whether detection box `det` may be assigned to track `t` (predicted already).
  bool gateAccepts(const cv::Rect2f& det, const Track& t) const;

  BoxTrackerParams params_;
  std::vector<Track> tracks_;
  int next_id_ = 0;
  int previous_output_ = 0;
};

}  // namespace tkgslam::dynamic
