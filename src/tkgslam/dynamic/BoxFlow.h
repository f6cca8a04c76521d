#pragma once
// Moves boxes of dynamic objects from one frame to the next by sparse optical flow ("median
// flow"): a grid of points inside each box is tracked with pyramidal Lucas-Kanade forward and
// back; points whose forward-backward error is small vote, the box moves by their median
// displacement and scales by the median ratio of their pairwise distances. With depth, only
// points on the nearest surface in the box vote (a person's box is half background, which moves
// with the camera, not with the person).
// Why: the detector runs every N-th frame (or its result arrives N frames late) and people near
// the camera move a whole box width in that time; a constant-velocity Kalman prediction only knows
// the motion between past detections, the flow measures it on every frame for about 1 ms.
#include <optional>
#include <vector>

#include <opencv2/core.hpp>

namespace tkgslam::dynamic {

struct BoxFlowParams {
  int grid = 6;                 ///< grid x grid points per box (36: enough votes for a median)
  float scale = 0.5f;           ///< flow runs on the image resized by this (speed; boxes are big)
  int window = 15;              ///< LK window (pixels of the resized image)
  int levels = 2;               ///< pyramid levels above the resized image
  float max_fb_error = 2.0f;    ///< forward-backward error (pixels) a point may have to vote
  int min_points = 8;           ///< fewer voting points: the box is not moved (no measurement)
  float max_scale_step = 0.02f; ///< the box grows or shrinks at most this much per frame
  /// Points farther than this (metres) behind the box's 25th-percentile depth do not vote.
  float foreground_band = 0.3f;
};

/// One frame's image pyramid, built once and used for every box and both directions.
struct FlowFrame {
  std::vector<cv::Mat> pyramid;  ///< of the image resized by BoxFlowParams::scale
  cv::Size size;                 ///< of the full image
  cv::Mat depth_m;  ///< CV_32F metres, 0 = invalid; empty: every point votes
};

class BoxFlow {
 public:
  explicit BoxFlow(const BoxFlowParams& params = {}) : params_(params) {}

  /// Builds the pyramid of an 8-bit grey or BGR image; keeps a reference to its depth (CV_32F,
  /// metres, registered to the image; may be empty).
  FlowFrame prepare(const cv::Mat& image, const cv::Mat& depth_m = {}) const;

  /// Each box (pixels of `from`) moved to `to`; nullopt where too few points tracked reliably.
  std::vector<std::optional<cv::Rect2f>> propagate(const FlowFrame& from, const FlowFrame& to,
                                                   const std::vector<cv::Rect2f>& boxes) const;

 private:
  /// Appends the grid points on the box's nearest surface (all of them without enough depth).
  void appendForeground(const std::vector<cv::Point2f>& grid, const std::vector<float>& depth,
                        std::vector<cv::Point2f>& points) const;

  BoxFlowParams params_;
};

}  // namespace tkgslam::dynamic
