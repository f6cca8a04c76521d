#include "tkgslam/data/FrameFeatures.h"

#include <algorithm>
#include <limits>
#include <cmath>

namespace tkgslam::data {

std::vector<int> FrameFeatures::featuresInArea(float x, float y, float r, int min_level, int max_level) const {
  std::vector<int> out;
  if (grid_start.empty()) return out;
  const int c0 = std::max(0, int(std::floor((x - min_x - r) * cell_w_inv)));
  const int c1 = std::min(kGridCols - 1, int(std::ceil((x - min_x + r) * cell_w_inv)));
  const int r0 = std::max(0, int(std::floor((y - min_y - r) * cell_h_inv)));
  const int r1 = std::min(kGridRows - 1, int(std::ceil((y - min_y + r) * cell_h_inv)));
  if (c0 > kGridCols - 1 || c1 < 0 || r0 > kGridRows - 1 || r1 < 0) return out;
  const int lo = min_level >= 0 ? min_level : std::numeric_limits<int>::min();
  const int hi = max_level >= 0 ? max_level : std::numeric_limits<int>::max();
  for (int gy = r0; gy <= r1; ++gy) {
    const GridKey* k = grid_keys.data() + grid_start[size_t(gy * kGridCols + c0)];
    const GridKey* end = grid_keys.data() + grid_start[size_t(gy * kGridCols + c1 + 1)];
    for (; k != end; ++k) {
      if (k->octave < lo || k->octave > hi) continue;
      if (std::abs(k->x - x) < r && std::abs(k->y - y) < r) out.push_back(k->index);
    }
  }
  return out;
}

void indexFeatures(FrameFeatures& f, const camera::PinholeCamera& camera) {
  using F = FrameFeatures;
  f.min_x = float(camera.minX());
  f.max_x = float(camera.maxX());
  f.min_y = float(camera.minY());
  f.max_y = float(camera.maxY());
  f.cell_w_inv = F::kGridCols / (f.max_x - f.min_x);
  f.cell_h_inv = F::kGridRows / (f.max_y - f.min_y);
  // Counting sort by cell: stable, so each cell's keypoints stay by ascending index.
  std::vector<int> cell(size_t(f.size()), -1);
  f.grid_start.assign(F::kGridCols * F::kGridRows + 1, 0);
  for (int i = 0; i < f.size(); ++i) {
    const int gx = int(std::floor((f.ideal[i].pt.x - f.min_x) * f.cell_w_inv));
    const int gy = int(std::floor((f.ideal[i].pt.y - f.min_y) * f.cell_h_inv));
    if (gx < 0 || gy < 0 || gx >= F::kGridCols || gy >= F::kGridRows) continue;
    cell[size_t(i)] = gy * F::kGridCols + gx;
    ++f.grid_start[size_t(cell[size_t(i)]) + 1];
  }
  for (size_t c = 1; c < f.grid_start.size(); ++c) f.grid_start[c] += f.grid_start[c - 1];
  f.grid_keys.resize(size_t(f.grid_start.back()));
  std::vector<int> fill(f.grid_start.begin(), f.grid_start.end() - 1);
  for (int i = 0; i < f.size(); ++i) {
    if (cell[size_t(i)] < 0) continue;
    const auto& kp = f.ideal[size_t(i)];
    f.grid_keys[size_t(fill[size_t(cell[size_t(i)])]++)] = {kp.pt.x, kp.pt.y, kp.octave, i};
  }
}

std::shared_ptr<FrameFeatures> makeFrameFeatures(feature::OrbFeatures orb, const cv::Mat& bgr, const cv::Mat& depth_m,
                                                 const camera::PinholeCamera& camera, const DepthParams& dp) {
  auto f = std::make_shared<FrameFeatures>();
  f->raw = std::move(orb.keypoints);
  f->descriptors = orb.descriptors;
  const int n = f->size();
  std::vector<cv::Point2f> pts(n);
  for (int i = 0; i < n; ++i) pts[i] = f->raw[i].pt;
  const auto und = camera.undistort(pts);
  f->ideal = f->raw;
  f->depth.assign(n, 0.0f);
  f->u_right.assign(n, -1.0f);
  f->excluded.assign(n, 0);
  f->colour.assign(n, cv::Vec3b(128, 128, 128));
  for (int i = 0; i < n; ++i) {
    f->ideal[i].pt = und[i];
    const int u = cvRound(f->raw[i].pt.x), v = cvRound(f->raw[i].pt.y);
    if (!bgr.empty() && bgr.type() == CV_8UC3 && u >= 0 && v >= 0 && u < bgr.cols && v < bgr.rows) {
      f->colour[i] = bgr.at<cv::Vec3b>(v, u);
    }
    if (!depth_m.empty() && u >= 0 && v >= 0 && u < depth_m.cols && v < depth_m.rows) {
      const float d = depth_m.at<float>(v, u);
      if (d > 0 && d < dp.max_depth && std::isfinite(d)) {
        f->depth[i] = d;
        f->u_right[i] = float(und[i].x - dp.baseline_fx / d);
      }
    }
  }
  indexFeatures(*f, camera);
  return f;
}

}  // namespace tkgslam::data
