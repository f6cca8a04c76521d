#pragma once
// The per-image feature data shared (immutably) by a Frame and the KeyFrame made from it:
// keypoints in raw and ideal (undistorted) pixels, their depth, ORB descriptors, and a grid
// index for fast radius queries in ideal-pixel coordinates.
#include <memory>
#include <vector>

#include <opencv2/core.hpp>

#include "tkgslam/camera/PinholeCamera.h"
#include "tkgslam/feature/OrbExtractor.h"
#include "tkgslam/camera/DepthParams.h"

namespace tkgslam::data {

struct FrameFeatures {
  static constexpr int kGridCols = 64;
  static constexpr int kGridRows = 48;

  std::vector<cv::KeyPoint> raw;    ///< detected keypoints, raw pixels (octave, angle, size)
  std::vector<cv::KeyPoint> ideal;  ///< same keypoints, undistorted pixel positions
  std::vector<float> depth;         ///< metres along the optical axis, 0 = none
  std::vector<float> u_right;       ///< virtual right-camera u = u - bf / depth, < 0 = none
  cv::Mat descriptors;              ///< N x 32 bytes
  std::vector<char> excluded;       ///< 1 = keypoint must not be used (e.g. on a dynamic object)
  std::vector<cv::Vec3b> colour;    ///< BGR colour at the keypoint (for the exported map)
  double sharpness = -1;            ///< feature::imageSharpness of the image, < 0 = not measured

  float min_x = 0, max_x = 0, min_y = 0, max_y = 0;  ///< image bounds in ideal pixels
  float cell_w_inv = 0, cell_h_inv = 0;
  /// The grid, kGridCols x kGridRows cells over the bounds, row-major, stored flat: cell c's
  /// keypoints are grid_keys[grid_start[c], grid_start[c + 1]), by ascending index, with the fields
  /// a radius query reads (a row of cells is one contiguous run: no pointer chasing per cell).
  struct GridKey {
    float x, y;  ///< ideal pixels
    int octave;
    int index;   ///< into raw / ideal / ...
  };
  std::vector<int> grid_start;  ///< kGridCols * kGridRows + 1 offsets
  std::vector<GridKey> grid_keys;

  int size() const { return static_cast<int>(raw.size()); }
  bool hasDepth(int i) const { return depth[i] > 0; }

  /// Indices of keypoints within radius r (square window) of (x, y) in ideal pixels whose octave
  /// is in [min_level, max_level] (negative = unbounded).
  std::vector<int> featuresInArea(float x, float y, float r, int min_level = -1, int max_level = -1) const;
};

/// Sets the image bounds and fills the grid from the ideal keypoints (makeFrameFeatures does;
/// also for features read back from a map file).
void indexFeatures(FrameFeatures& features, const camera::PinholeCamera& camera);

/// Builds the features of one RGB-D image: undistorts keypoints, attaches depth (looked up at
/// the raw keypoint pixel; depth is registered to colour) and fills the grid.
std::shared_ptr<FrameFeatures> makeFrameFeatures(feature::OrbFeatures orb, const cv::Mat& bgr, const cv::Mat& depth_m,
                                                 const camera::PinholeCamera& camera, const DepthParams& depth);

}  // namespace tkgslam::data
