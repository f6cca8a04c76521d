#include "tkgslam/dynamic/BoxKalmanFilter.h"

#include <cmath>

#include <Eigen/LU>

namespace tkgslam::dynamic {

namespace {
Eigen::Matrix<double, 7, 7> transition() {
  Eigen::Matrix<double, 7, 7> F = Eigen::Matrix<double, 7, 7>::Identity();
  F(0, 4) = F(1, 5) = F(2, 6) = 1.0;  // dt = 1 frame
  return F;
}
Eigen::Matrix<double, 4, 7> observation() {
  Eigen::Matrix<double, 4, 7> H = Eigen::Matrix<double, 4, 7>::Zero();
  H.leftCols<4>().setIdentity();
  return H;
}
}  // namespace

Eigen::Vector4d BoxKalmanFilter::boxToMeasurement(const cv::Rect2f& b) {
  return {b.x + 0.5 * b.width, b.y + 0.5 * b.height, double(b.width) * b.height,
          b.height > 0 ? double(b.width) / b.height : 1.0};
}

cv::Rect2f BoxKalmanFilter::stateToBox(const State& x) {
  const double s = std::max(x[2], 0.0), r = std::max(x[3], 1e-6);
  const double w = std::sqrt(s * r), h = r > 0 ? s / std::max(w, 1e-9) : 0.0;
  return cv::Rect2f(float(x[0] - w / 2), float(x[1] - h / 2), float(w), float(h));
}

BoxKalmanFilter::BoxKalmanFilter(const cv::Rect2f& box, const KalmanParams& params) : params_(params) {
  x_.setZero();
  x_.head<4>() = boxToMeasurement(box);
  P_.setZero();
  P_.diagonal() << params.p0, params.p0, params.p0, params.p0, params.p0_velocity, params.p0_velocity,
      params.p0_velocity;
}

cv::Rect2f BoxKalmanFilter::predict() {
  if (x_[2] + x_[6] <= 0) x_[6] = 0;  // the area cannot become negative
  static const auto F = transition();
  x_ = F * x_;
  P_ = F * P_ * F.transpose() + params_.q * Cov::Identity();
  return box();
}

void BoxKalmanFilter::follow(const cv::Rect2f& box) {
  const Eigen::Vector4d z = boxToMeasurement(box);
  const Eigen::Vector3d previous = x_.head<3>() - x_.segment<3>(4);  // state before predict()
  x_.segment<3>(4) = 0.5 * (x_.segment<3>(4) + (z.head<3>() - previous));
  x_.head<4>() = z;
}

void BoxKalmanFilter::update(const cv::Rect2f& box) {
  static const auto H = observation();
  const Eigen::Vector4d z = boxToMeasurement(box);
  const Eigen::Vector4d y = z - H * x_;
  const Eigen::Matrix4d S = H * P_ * H.transpose() + params_.r * Eigen::Matrix4d::Identity();
  const Eigen::Matrix<double, 7, 4> K = P_ * H.transpose() * S.inverse();
  x_ += K * y;
  P_ = (Cov::Identity() - K * H) * P_;
}

}  // namespace tkgslam::dynamic
