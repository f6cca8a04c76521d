#include "tkgslam/dynamic/BoxFlow.h"

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>
#include <opencv2/video/tracking.hpp>

namespace tkgslam::dynamic {

namespace {
float median(std::vector<float> v) {
  const auto mid = v.begin() + long(v.size() / 2);
  std::nth_element(v.begin(), mid, v.end());
  return *mid;
}
}  // namespace

FlowFrame BoxFlow::prepare(const cv::Mat& image, const cv::Mat& depth_m) const {
  FlowFrame f;
  if (!depth_m.empty() && depth_m.type() == CV_32F && depth_m.size() == image.size()) f.depth_m = depth_m;
  cv::Mat grey = image;
  if (image.channels() == 3) cv::cvtColor(image, grey, cv::COLOR_BGR2GRAY);
  f.size = grey.size();
  if (params_.scale != 1.0f) cv::resize(grey, grey, cv::Size(), params_.scale, params_.scale, cv::INTER_AREA);
  cv::buildOpticalFlowPyramid(grey, f.pyramid, cv::Size(params_.window, params_.window), params_.levels);
  return f;
}

void BoxFlow::appendForeground(const std::vector<cv::Point2f>& grid, const std::vector<float>& depth,
                               std::vector<cv::Point2f>& points) const {
  std::vector<float> valid;
  for (float d : depth) {
    if (d > 0) valid.push_back(d);
  }
  if (params_.foreground_band <= 0 || int(valid.size()) < params_.min_points) {
    points.insert(points.end(), grid.begin(), grid.end());
    return;
  }
  const auto q = valid.begin() + long(valid.size() / 4);
  std::nth_element(valid.begin(), q, valid.end());
  const float limit = *q + params_.foreground_band;
  for (size_t k = 0; k < grid.size(); ++k) {
    if (depth[k] > 0 && depth[k] <= limit) points.push_back(grid[k]);
  }
}

std::vector<std::optional<cv::Rect2f>> BoxFlow::propagate(const FlowFrame& from, const FlowFrame& to,
                                                          const std::vector<cv::Rect2f>& boxes) const {
  std::vector<std::optional<cv::Rect2f>> out(boxes.size());
  if (boxes.empty() || from.pyramid.empty() || to.pyramid.empty() || from.size != to.size) return out;
  const cv::Rect2f image(0, 0, float(from.size.width), float(from.size.height));

  // Grid points of every box (inside the image), all tracked in one call per direction.
  std::vector<cv::Point2f> points;
  std::vector<size_t> first(boxes.size() + 1, 0);
  const int n = params_.grid;
  for (size_t b = 0; b < boxes.size(); ++b) {
    first[b] = points.size();
    const cv::Rect2f r = boxes[b] & image;
    if (r.width < 2 || r.height < 2) continue;
    std::vector<cv::Point2f> grid;
    std::vector<float> depth;  // per grid point, 0 = unknown
    for (int i = 0; i < n; ++i) {
      for (int j = 0; j < n; ++j) {
        grid.emplace_back(r.x + r.width * (j + 0.5f) / n, r.y + r.height * (i + 0.5f) / n);
        depth.push_back(from.depth_m.empty() ? 0.0f : from.depth_m.at<float>(cv::Point(grid.back())));
      }
    }
    appendForeground(grid, depth, points);
  }
  first[boxes.size()] = points.size();
  if (points.empty()) return out;

  const cv::Size window(params_.window, params_.window);
  const cv::TermCriteria stop(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 20, 0.03);
  std::vector<cv::Point2f> small, forward, back;
  std::vector<uchar> ok_f, ok_b;
  std::vector<float> err;
  for (const auto& p : points) small.push_back(p * params_.scale);
  cv::calcOpticalFlowPyrLK(from.pyramid, to.pyramid, small, forward, ok_f, err, window, params_.levels, stop);
  cv::calcOpticalFlowPyrLK(to.pyramid, from.pyramid, forward, back, ok_b, err, window, params_.levels, stop);
  // Back to full-image pixels.
  for (auto& p : forward) p /= params_.scale;
  for (auto& p : back) p /= params_.scale;

  for (size_t b = 0; b < boxes.size(); ++b) {
    std::vector<size_t> good;
    for (size_t k = first[b]; k < first[b + 1]; ++k) {
      if (ok_f[k] && ok_b[k] && cv::norm(back[k] - points[k]) <= params_.max_fb_error) good.push_back(k);
    }
    if (int(good.size()) < params_.min_points) continue;
    std::vector<float> dx, dy, scale;
    for (size_t k : good) {
      dx.push_back(forward[k].x - points[k].x);
      dy.push_back(forward[k].y - points[k].y);
    }
    // Scale from pairs of voting points that are far enough apart to measure it (a strided
    // subset keeps this linear in the number of points).
    for (size_t a = 0; a < good.size(); ++a) {
      const size_t c = good[(a + good.size() / 2) % good.size()];
      const float d0 = float(cv::norm(points[good[a]] - points[c]));
      if (d0 > 4.0f) scale.push_back(float(cv::norm(forward[good[a]] - forward[c])) / d0);
    }
    const float s = scale.empty() ? 1.0f
                                  : std::clamp(median(scale), 1.0f - params_.max_scale_step, 1.0f + params_.max_scale_step);
    const cv::Rect2f& r = boxes[b];
    const float cx = r.x + 0.5f * r.width + median(dx), cy = r.y + 0.5f * r.height + median(dy);
    float x0 = cx - 0.5f * s * r.width, y0 = cy - 0.5f * s * r.height;
    float x1 = cx + 0.5f * s * r.width, y1 = cy + 0.5f * s * r.height;
    // A box touching the image border is an object cut by it: what moves into view is more of
    // the object, so that edge stays on the border (a box leaving the image shrinks instead).
    const float edge = 1.0f;
    if (r.x <= image.x + edge) x0 = std::min(x0, image.x);
    if (r.y <= image.y + edge) y0 = std::min(y0, image.y);
    if (r.br().x >= image.br().x - edge) x1 = std::max(x1, image.br().x);
    if (r.br().y >= image.br().y - edge) y1 = std::max(y1, image.br().y);
    out[b] = cv::Rect2f(x0, y0, x1 - x0, y1 - y0);
  }
  return out;
}

}  // namespace tkgslam::dynamic
