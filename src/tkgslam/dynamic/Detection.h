#pragma once
// A detected (or Kalman-predicted) box of an a-priori dynamic object, in raw image pixels.
#include <opencv2/core.hpp>

namespace tkgslam::dynamic {

struct Detection {
  cv::Rect2f box;          ///< x, y = top-left corner; pixels of the input image
  int class_id = 0;        ///< COCO class id (0 = person)
  float score = 0;         ///< objectness x class score, in [0, 1]
  bool predicted = false;  ///< filled in by the box tracker for a missed detection
  int track_id = -1;
};

/// Intersection over union of two boxes (0 when either is empty).
inline float iou(const cv::Rect2f& a, const cv::Rect2f& b) {
  const float inter = (a & b).area();
  const float uni = a.area() + b.area() - inter;
  return uni > 0 ? inter / uni : 0.0f;
}

}  // namespace tkgslam::dynamic
