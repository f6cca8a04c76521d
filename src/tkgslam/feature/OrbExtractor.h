#pragma once
// ORB features as ORB-SLAM2 extracts them: an image pyramid, FAST corners kept per grid cell
// (with a lower threshold where a cell has no corner), spread evenly with a quadtree, oriented by
// the intensity centroid, and described by OpenCV's learned rBRIEF (256 bits).
#include <vector>

#include <opencv2/core.hpp>
#include <opencv2/features2d.hpp>

#include "tkgslam/feature/ScalePyramid.h"

namespace tkgslam::feature {

struct OrbParams {
  int features = 1000;       ///< total keypoints over all levels
  double scale_factor = 1.2; ///< pyramid scale between levels
  int levels = 8;
  int fast_threshold = 20;     ///< FAST threshold tried first in each cell
  int fast_min_threshold = 7;  ///< used in cells where the first finds nothing
};

/// Keypoints in raw (distorted) level-0 pixel coordinates; `octave` is the pyramid level,
/// `angle` in degrees, `size` the patch diameter at level 0. Descriptors: one row of 32 bytes each.
struct OrbFeatures {
  std::vector<cv::KeyPoint> keypoints;
  cv::Mat descriptors;
};

/// What an extraction found before it chose keypoints: the image pyramid and every FAST corner
/// (at the low threshold, in level pixel coordinates) of each level. Kept, it lets
/// OrbExtractor::extractAgain spend the budget elsewhere without detecting again.
struct OrbDetections {
  std::vector<cv::Mat> levels;
  std::vector<std::vector<cv::KeyPoint>> corners;
};

class OrbExtractor {
 public:
  /// Throws InputError for invalid parameters.
  explicit OrbExtractor(const OrbParams& params);

  /// Extracts features from an 8-bit grey image. Deterministic; thread-safe. With a `skip` mask
  /// (8-bit, image size, non-zero = no keypoints there) the whole budget goes to the rest.
  /// With `detections`, also returns what extractAgain needs.
  OrbFeatures extract(const cv::Mat& gray, const cv::Mat& skip = {}, OrbDetections* detections = nullptr) const;

  /// The same features as extract(gray, skip), from the detections an earlier extraction of
  /// `gray` kept (no second pyramid or FAST pass); keypoints `previous` (that extraction's result)
  /// already has keep their descriptors instead of being described again. About 3x cheaper.
  OrbFeatures extractAgain(const OrbDetections& detections, const cv::Mat& gray, const cv::Mat& skip,
                           const OrbFeatures& previous) const;

  const OrbParams& params() const { return params_; }
  int levels() const { return params_.levels; }
  const ScalePyramid& pyramid() const { return pyramid_; }

 private:
  /// All FAST corners of a level image at the low threshold, inside the border.
  std::vector<cv::KeyPoint> detectCorners(const cv::Mat& level_image) const;
  /// The level's share of keypoints among `corners` outside `skip`: strong corners where a cell
  /// has them, spread by the quadtree, oriented; returned in the level's pixel coordinates.
  std::vector<cv::KeyPoint> selectKeypoints(const cv::Mat& level_image, int level,
                                            const std::vector<cv::KeyPoint>& corners, const cv::Mat& skip) const;
  /// rBRIEF descriptors (one 32-byte row each) of keypoints in a level image's coordinates.
  cv::Mat describeLevel(const cv::Mat& level_image, const std::vector<cv::KeyPoint>& kps) const;
  /// Level pixel coordinates to level-0 ones.
  void toLevelZero(std::vector<cv::KeyPoint>& kps, int level) const;
  void checkInputs(const cv::Mat& gray, const cv::Mat& skip) const;

  OrbParams params_;
  ScalePyramid pyramid_;
  std::vector<int> features_per_level_;
  std::vector<int> umax_;  // half-width of each row of the circular orientation patch
  cv::Ptr<cv::ORB> descriptor_;
};

/// Spreads keypoints evenly over [min, max) with a quadtree (ORB-SLAM2's scheme): cells are split
/// until there are about `target` of them, then the strongest keypoint of each cell is kept.
std::vector<cv::KeyPoint> distributeQuadtree(const std::vector<cv::KeyPoint>& keypoints, int min_x,
                                             int max_x, int min_y, int max_y, int target);

}  // namespace tkgslam::feature
