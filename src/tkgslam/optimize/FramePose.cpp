#include "tkgslam/optimize/FramePose.h"

#include <opencv2/calib3d.hpp>

#include "tkgslam/data/MapPoint.h"

namespace tkgslam::optimize {

int solvePnpRansac(const data::Frame& frame, const camera::PinholeCamera& camera,
                   std::vector<std::shared_ptr<data::MapPoint>>& matches, Pose& T_cw) {
  const auto& F = *frame.features;
  std::vector<cv::Point3f> obj;
  std::vector<cv::Point2f> img;
  std::vector<int> idx;
  for (int i = 0; i < frame.size(); ++i) {
    if (!matches[i]) continue;
    const Vec3& p = matches[i]->pos_w;
    obj.emplace_back(float(p.x()), float(p.y()), float(p.z()));
    img.push_back(F.ideal[i].pt);
    idx.push_back(i);
  }
  if (obj.size() < 6) return 0;
  const cv::Matx33d K(camera.fx(), 0, camera.cx(), 0, camera.fy(), camera.cy(), 0, 0, 1);
  cv::Mat rvec, tvec;
  std::vector<int> inliers;
  if (!cv::solvePnPRansac(obj, img, K, cv::noArray(), rvec, tvec, false, 200, 4.0f, 0.99, inliers,
                          cv::SOLVEPNP_EPNP) ||
      inliers.empty()) {
    return 0;
  }
  cv::Mat R;
  cv::Rodrigues(rvec, R);
  T_cw = Pose::Identity();
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) T_cw.linear()(r, c) = R.at<double>(r, c);
    T_cw.translation()[r] = tvec.at<double>(r);
  }
  std::vector<std::shared_ptr<data::MapPoint>> kept(matches.size());
  for (int i : inliers) kept[idx[i]] = matches[idx[i]];
  matches = std::move(kept);
  return int(inliers.size());
}

int optimizeFramePose(data::Frame& frame, const PinholeIntrinsics& K, const feature::ScalePyramid& pyramid) {
  const auto& F = *frame.features;
  std::vector<PoseObservation> obs;
  std::vector<int> index;
  for (int i = 0; i < frame.size(); ++i) {
    if (!frame.map_points[i]) continue;
    PoseObservation o;
    o.p_w = frame.map_points[i]->pos_w;
    o.uv = Vec2(F.ideal[i].pt.x, F.ideal[i].pt.y);
    o.u_right = F.u_right[i];
    o.information = pyramid.inv_sigma2[F.ideal[i].octave];
    obs.push_back(o);
    index.push_back(i);
  }
  std::vector<char> outlier;
  const int inliers = optimizePose(obs, K, frame.T_cw, outlier);
  for (size_t k = 0; k < index.size(); ++k) frame.outlier[index[k]] = outlier[k];
  return inliers;
}

}  // namespace tkgslam::optimize
