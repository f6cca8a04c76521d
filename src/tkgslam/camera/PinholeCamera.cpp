#include "tkgslam/camera/PinholeCamera.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>
#include <opencv2/calib3d.hpp>

#include "tkgslam/common/Error.h"

namespace tkgslam::camera {

PinholeCamera::PinholeCamera(const CameraParams& params) : p_(params) {
  if (!(p_.width > 0 && p_.height > 0)) {
    throw InputError(fmt::format("camera: image size must be positive (got {}x{})", p_.width, p_.height));
  }
  if (!(p_.fx > 0) || !(p_.fy > 0)) {
    throw InputError(fmt::format("camera: fx and fy must be > 0 (got fx={}, fy={})", p_.fx, p_.fy));
  }
  if (!(p_.cx >= 0 && p_.cx < p_.width && p_.cy >= 0 && p_.cy < p_.height)) {
    throw InputError(fmt::format("camera: principal point ({}, {}) is outside the {}x{} image", p_.cx,
                                 p_.cy, p_.width, p_.height));
  }
  if (!(p_.fps > 0)) throw InputError("camera: fps must be > 0");
  for (double d : p_.distortion) {
    if (!std::isfinite(d)) throw InputError("camera: distortion coefficients must be finite");
    if (d != 0.0) has_distortion_ = true;
  }
  // Image bounds after undistortion: undistort the four corners (as ORB-SLAM2 does).
  const float w = float(p_.width), h = float(p_.height);
  const auto c = undistort({{0, 0}, {w, 0}, {0, h}, {w, h}});
  min_x_ = std::min(c[0].x, c[2].x);
  max_x_ = std::max(c[1].x, c[3].x);
  min_y_ = std::min(c[0].y, c[1].y);
  max_y_ = std::max(c[2].y, c[3].y);
}

Vec2 PinholeCamera::distort(const Vec2& ideal) const {
  if (!has_distortion_) return ideal;
  const auto& d = p_.distortion;
  const double x = (ideal.x() - p_.cx) / p_.fx, y = (ideal.y() - p_.cy) / p_.fy;
  const double r2 = x * x + y * y;
  const double radial = 1 + d[0] * r2 + d[1] * r2 * r2 + d[4] * r2 * r2 * r2;
  const double xd = x * radial + 2 * d[2] * x * y + d[3] * (r2 + 2 * x * x);
  const double yd = y * radial + d[2] * (r2 + 2 * y * y) + 2 * d[3] * x * y;
  return {p_.fx * xd + p_.cx, p_.fy * yd + p_.cy};
}

std::vector<cv::Point2f> PinholeCamera::undistort(const std::vector<cv::Point2f>& raw) const {
  if (!has_distortion_ || raw.empty()) return raw;
  const cv::Matx33d K(p_.fx, 0, p_.cx, 0, p_.fy, p_.cy, 0, 0, 1);
  const cv::Vec<double, 5> dist(p_.distortion[0], p_.distortion[1], p_.distortion[2], p_.distortion[3],
                                p_.distortion[4]);
  std::vector<cv::Point2f> out;
  cv::undistortPoints(raw, out, K, dist, cv::noArray(), K);
  return out;
}

}  // namespace tkgslam::camera
