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
/// at least `min_height` pixels tall. With `whole_only`, only whole upright people: the
/// segmentation spans the box from head to feet (>= 85 % of its height; GrabCut on a dark,
/// blurred photo may keep just a torso) and the box is at most 0.45 as wide as tall (a standing
/// person; a sitting one or a half body cut off by the photo is wider). Throws InputError if
/// the folder has no usable image.
std::vector<PersonCutout> extractPersonCutouts(const std::string& folder, dynamic::YoloDetector& detector,
                                               int min_height = 150, float min_score = 0.5f, bool whole_only = false);

/// Whether a cut-out's mask (255 = person) spans its box from head to feet and the box has a
/// standing person's shape (see extractPersonCutouts).
bool isWholeUprightPerson(const cv::Mat& mask);

/// GrabCut segmentation of the object inside `box` (initialised from the box).
cv::Mat segmentInBox(const cv::Mat& bgr, const cv::Rect& box);

}  // namespace tkgslam::augment
