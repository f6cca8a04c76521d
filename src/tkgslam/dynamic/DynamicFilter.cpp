#include "tkgslam/dynamic/DynamicFilter.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include <opencv2/imgproc.hpp>

namespace tkgslam::dynamic {

namespace {
bool inMask(const cv::Mat& mask, const cv::Point2f& p) {
  const int u = cvRound(p.x), v = cvRound(p.y);
  return u >= 0 && v >= 0 && u < mask.cols && v < mask.rows && mask.at<uchar>(v, u);
}
}  // namespace

BoxMask rasterizeBoxes(const std::vector<Detection>& boxes, cv::Size image, double margin) {
  BoxMask m;
  m.mask = cv::Mat::zeros(image, CV_8U);
  const cv::Rect frame(0, 0, image.width, image.height);
  for (const auto& d : boxes) {
    const float mx = float(margin) * d.box.width, my = float(margin) * d.box.height;
    const cv::Rect r = cv::Rect(cv::Point(int(std::floor(d.box.x - mx)), int(std::floor(d.box.y - my))),
                                cv::Point(int(std::ceil(d.box.br().x + mx)), int(std::ceil(d.box.br().y + my)))) &
                       frame;
    if (r.area() > 0) m.mask(r).setTo(255);
  }
  m.ratio = image.area() > 0 ? double(cv::countNonZero(m.mask)) / image.area() : 0.0;
  return m;
}

int excludeKeypointsInMask(data::FrameFeatures& f, const cv::Mat& mask) {
  int n = 0;
  for (int i = 0; i < f.size(); ++i) {
    if (inMask(mask, f.raw[i].pt)) {
      f.excluded[i] = 1;
      ++n;
    }
  }
  return n;
}

std::vector<int> selectReferenceViews(const Pose& T_cw, const std::vector<Pose>& candidates, int n) {
  const size_t m = candidates.size();
  if (m == 0 || n <= 0) return {};
  const Vec3 c_cur = T_cw.inverse().translation();
  std::vector<double> trans(m), rot(m);
  for (size_t i = 0; i < m; ++i) {
    trans[i] = (candidates[i].inverse().translation() - c_cur).norm();
    const Mat3 R_rel = candidates[i].linear() * T_cw.linear().transpose();
    Vec3 euler = R_rel.eulerAngles(2, 1, 0);
    for (int k = 0; k < 3; ++k) {  // wrap each angle to [-pi, pi] and take its magnitude
      euler[k] = std::remainder(euler[k], 2 * M_PI);
    }
    rot[i] = euler.norm();
    // eulerAngles may return an equivalent triple with angles near pi: use the smaller magnitude.
    rot[i] = std::min(rot[i], rotationAngle(R_rel) * std::sqrt(3.0));
  }
  const double max_t = *std::max_element(trans.begin(), trans.end());
  const double max_r = *std::max_element(rot.begin(), rot.end());
  std::vector<double> dist(m);
  for (size_t i = 0; i < m; ++i) {
    dist[i] = 0.7 * (max_t > 0 ? trans[i] / max_t : 0.0) + 0.3 * (max_r > 0 ? rot[i] / max_r : 0.0);
  }
  std::vector<int> order(m);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return dist[a] < dist[b]; });
  order.resize(std::min<size_t>(m, size_t(n)));
  return order;
}

GeometryResult checkMultiViewGeometry(const Pose& T_cw, const cv::Mat& depth_m, const cv::Mat& box_mask,
                                      const std::vector<ReferenceView>& refs, const camera::PinholeCamera& cam,
                                      const GeometryParams& p) {
  GeometryResult result;
  result.dynamic_region = cv::Mat::zeros(depth_m.size(), CV_8U);
  const Vec3 c_cur = T_cw.inverse().translation();
  const double cos_max = std::cos(p.max_parallax_deg * M_PI / 180.0);
  std::vector<cv::Point> seeds;
  for (const auto& ref : refs) {
    const auto& F = *ref.features;
    const Pose T_wr = ref.T_cw.inverse();
    const Vec3 c_ref = T_wr.translation();
    for (int i = 0; i < F.size(); ++i) {
      const float d = F.depth[i];
      if (!(d > 0 && d < p.reference_max_depth) || F.excluded[i]) continue;
      const Vec3 P = T_wr * cam.unproject(Vec2(F.ideal[i].pt.x, F.ideal[i].pt.y), d);
      const Vec3 a = P - c_ref, b = P - c_cur;
      if (a.dot(b) < cos_max * a.norm() * b.norm()) continue;  // parallax above the limit
      const Vec3 pc = T_cw * P;
      const double z_proj = pc.z();
      if (!(z_proj > 0 && z_proj < p.current_max_depth)) continue;
      const Vec2 raw = cam.distort(cam.project(pc));
      const int u = int(std::lround(raw.x())), v = int(std::lround(raw.y()));
      if (u < 0 || v < 0 || u >= depth_m.cols || v >= depth_m.rows) continue;
      if (!box_mask.at<uchar>(v, u)) continue;  // only the boxes are in question
      ++result.projected;
      // z' = the valid depth in (0, z_proj) closest to z_proj within the patch.
      double z_best = 0, sum = 0, sum_sq = 0;
      int count = 0;
      for (int dv = -p.patch_radius; dv <= p.patch_radius; ++dv) {
        const int y = v + dv;
        if (y < 0 || y >= depth_m.rows) continue;
        const float* row = depth_m.ptr<float>(y);
        for (int du = -p.patch_radius; du <= p.patch_radius; ++du) {
          const int x = u + du;
          if (x < 0 || x >= depth_m.cols) continue;
          const double z = row[x];
          if (z <= 0) continue;
          sum += z;
          sum_sq += z * z;
          ++count;
          if (z < z_proj && z > z_best) z_best = z;
        }
      }
      if (z_best <= 0 || z_proj - z_best <= p.occlusion_threshold) continue;
      const double mean = sum / count;
      const double var = std::max(0.0, sum_sq / count - mean * mean);
      if (std::sqrt(var) > p.max_patch_std) continue;  // complex occlusion at an edge: static
      ++result.evidence;
      seeds.emplace_back(u, v);
    }
  }
  if (seeds.empty()) return result;
  // Grow depth-consistent regions from the evidence, confined to the boxes.
  cv::Mat flood_mask(depth_m.rows + 2, depth_m.cols + 2, CV_8U, cv::Scalar(1));
  flood_mask(cv::Rect(1, 1, depth_m.cols, depth_m.rows)).setTo(0, box_mask);
  const int flags = 4 | cv::FLOODFILL_MASK_ONLY | (255 << 8);
  cv::Mat depth = depth_m.clone();  // floodFill requires a writable image even in mask-only mode
  for (const auto& s : seeds) {
    // Seed at the nearest surface in the patch (the occluder), not at a background pixel.
    cv::Point best = s;
    float z_min = std::numeric_limits<float>::max();
    for (int dv = -p.patch_radius; dv <= p.patch_radius; ++dv) {
      for (int du = -p.patch_radius; du <= p.patch_radius; ++du) {
        const cv::Point q(s.x + du, s.y + dv);
        if (q.x < 0 || q.y < 0 || q.x >= depth.cols || q.y >= depth.rows) continue;
        const float z = depth.at<float>(q);
        if (z > 0 && z < z_min && box_mask.at<uchar>(q)) z_min = z, best = q;
      }
    }
    if (z_min == std::numeric_limits<float>::max()) continue;   // no surface to grow from
    if (flood_mask.at<uchar>(best.y + 1, best.x + 1)) continue;  // already grown or outside
    cv::floodFill(depth, flood_mask, best, cv::Scalar(), nullptr, cv::Scalar(p.region_depth_step),
                  cv::Scalar(p.region_depth_step), flags);
  }
  // Region pixels were marked 255 (fill value); barriers were 1.
  cv::Mat inner = flood_mask(cv::Rect(1, 1, depth_m.cols, depth_m.rows));
  result.dynamic_region = (inner == 255);
  return result;
}

int readmitStaticKeypoints(data::FrameFeatures& f, const cv::Mat& box_mask, const cv::Mat& dynamic_region) {
  int n = 0;
  for (int i = 0; i < f.size(); ++i) {
    if (!f.excluded[i] || !inMask(box_mask, f.raw[i].pt)) continue;
    if (!dynamic_region.empty() && inMask(dynamic_region, f.raw[i].pt)) continue;
    f.excluded[i] = 0;
    ++n;
  }
  return n;
}

}  // namespace tkgslam::dynamic
