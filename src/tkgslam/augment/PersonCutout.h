#pragma once
// Cut-outs of real people from real photos: the detector finds each person, GrabCut segments it
// inside its box. Used to composite moving people into a static RGB-D sequence.
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "tkgslam/dynamic/YoloDetector.h"

namespace tkgslam::augment {

struct PersonCutout {
  cv::Mat bgr;   ///< the person's box from the photo
  cv::Mat mask;  ///< 255 on the person, 0 elsewhere (same size)
  std::string source;
};

/// Extracts the confidently detected persons of every image in `folder` (sorted by name) that are
/// at least `min_height` pixels tall. Throws InputError if the folder has no usable image.
std::vector<PersonCutout> extractPersonCutouts(const std::string& folder, dynamic::YoloDetector& detector,
                                               int min_height = 150, float min_score = 0.5f);

/// GrabCut segmentation of the object inside `box` (initialised from the box).
cv::Mat segmentInBox(const cv::Mat& bgr, const cv::Rect& box);

}  // namespace tkgslam::augment
