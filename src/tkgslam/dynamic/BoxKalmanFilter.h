#pragma once
// Constant-velocity Kalman filter of one box (SORT's model, the paper's §3.2):
// state X = [x, y, s, r, vx, vy, vs] with (x, y) the box centre in pixels (the paper writes
// top-left; the centre is better conditioned), s the area (px^2) and r = w / h; dt = 1 frame.
// Measurement z = [x, y, s, r].
#include <Eigen/Core>
#include <opencv2/core.hpp>

namespace tkgslam::dynamic {

struct KalmanParams {
  double q = 0.01;     ///< process noise Q = q * I7 (paper: 0.01)
  double r = 0.1;      ///< measurement noise R = r * I4 (paper: 0.1)
  double p0 = 10.0;    ///< initial variance of the measured components
  double p0_velocity = 1000.0;  ///< initial variance of the velocities (unobserved at birth)
};

class BoxKalmanFilter {
 public:
  using State = Eigen::Matrix<double, 7, 1>;
  using Cov = Eigen::Matrix<double, 7, 7>;

  BoxKalmanFilter(const cv::Rect2f& box, const KalmanParams& params);

  /// Propagates one frame; returns the predicted box.
  cv::Rect2f predict();
  /// Fuses a measured box.
  void update(const cv::Rect2f& box);
  /// After predict(): takes a box measured by frame-to-frame motion (optical flow) as the new
  /// position and the motion since the previous frame as the velocity (averaged with the old one).
  /// Not a Kalman update: with the paper's Q and R the filter would trust its old velocity for
  /// many frames, and flow is a direct measurement of the current motion.
  void follow(const cv::Rect2f& box);

  cv::Rect2f box() const { return stateToBox(x_); }
  const State& state() const { return x_; }
  const Cov& covariance() const { return P_; }

  static Eigen::Vector4d boxToMeasurement(const cv::Rect2f& box);
  static cv::Rect2f stateToBox(const State& x);

 private:
  KalmanParams params_;
  State x_;
  Cov P_;
};

}  // namespace tkgslam::dynamic
