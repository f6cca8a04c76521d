#pragma once
// Pinhole camera with radial-tangential (Brown-Conrady / OpenCV "plumb bob") distortion.
// Pixel coordinates: u right, v down, origin at the centre of the top-left pixel.
// Camera frame: x right, y down, z forward (metres). "Ideal" pixels are undistorted.
#include <array>
#include <vector>

#include <opencv2/core.hpp>

#include "tkgslam/common/Pose.h"

namespace tkgslam::camera {

struct CameraParams {
  int width = 640;
  int height = 480;
  double fx = 0, fy = 0, cx = 0, cy = 0;        ///< pixels
  std::array<double, 5> distortion{0, 0, 0, 0, 0};  ///< k1 k2 p1 p2 k3
  double fps = 30.0;
};

class PinholeCamera {
 public:
  /// Throws InputError if the parameters are invalid (fx, fy <= 0, size <= 0, centre outside).
  explicit PinholeCamera(const CameraParams& params);

  const CameraParams& params() const { return p_; }
  int width() const { return p_.width; }
  int height() const { return p_.height; }
  double fx() const { return p_.fx; }
  double fy() const { return p_.fy; }
  double cx() const { return p_.cx; }
  double cy() const { return p_.cy; }
  bool hasDistortion() const { return has_distortion_; }

  /// Projects a point in the camera frame (z > 0) to an ideal pixel.
  Vec2 project(const Vec3& p_c) const {
    const double iz = 1.0 / p_c.z();
    return {p_.fx * p_c.x() * iz + p_.cx, p_.fy * p_c.y() * iz + p_.cy};
  }
  /// Back-projects an ideal pixel with depth z (metres, along the optical axis).
  Vec3 unproject(const Vec2& uv, double z) const {
    return {(uv.x() - p_.cx) * z / p_.fx, (uv.y() - p_.cy) * z / p_.fy, z};
  }
  /// Ideal pixel -> raw (distorted) pixel, e.g. to look up the depth image.
  Vec2 distort(const Vec2& ideal) const;
  /// Raw (distorted) pixels -> ideal pixels.
  std::vector<cv::Point2f> undistort(const std::vector<cv::Point2f>& raw) const;

  /// Bounds of the undistorted image in ideal pixels (where projections can land).
  double minX() const { return min_x_; }
  double maxX() const { return max_x_; }
  double minY() const { return min_y_; }
  double maxY() const { return max_y_; }
  bool inImage(const Vec2& ideal) const {
    return ideal.x() >= min_x_ && ideal.x() < max_x_ && ideal.y() >= min_y_ && ideal.y() < max_y_;
  }

 private:
  CameraParams p_;
  bool has_distortion_ = false;
  double min_x_ = 0, max_x_ = 0, min_y_ = 0, max_y_ = 0;
};

}  // namespace tkgslam::camera
