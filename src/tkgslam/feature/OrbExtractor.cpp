#include "tkgslam/feature/OrbExtractor.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <list>
#include <unordered_map>

#include <fmt/format.h>
#include <opencv2/imgproc.hpp>

#include "tkgslam/common/Error.h"

namespace tkgslam::feature {

namespace {
constexpr int kPatchSize = 31;
constexpr int kHalfPatch = 15;
constexpr int kEdgeThreshold = 19;                  // descriptor patch border
constexpr int kFastBorder = kEdgeThreshold - 3;     // FAST needs 3 px around the centre
constexpr int kCellSize = 30;

/// The part of a level image where FAST corners are kept (a descriptor patch fits around them).
struct FastArea {
  int min_x, min_y, max_x, max_y;
};
FastArea fastArea(const cv::Mat& img) {
  return {kFastBorder, kFastBorder, img.cols - kFastBorder, img.rows - kFastBorder};
}

struct QuadNode {
  std::vector<cv::KeyPoint> kps;
  float x0, x1, y0, y1;
  bool leaf() const { return kps.size() <= 1; }
};

/// Descriptor rows stacked in order; 0 x 32 when there are none (vconcat needs at least one row).
cv::Mat stackDescriptors(const std::vector<cv::Mat>& parts) {
  int rows = 0;
  for (const auto& p : parts) rows += p.rows;
  if (rows == 0) return cv::Mat(0, 32, CV_8U);
  cv::Mat out;
  cv::vconcat(parts, out);
  return out;
}

void splitNode(const QuadNode& n, QuadNode out[4]) {
  const float xm = 0.5f * (n.x0 + n.x1), ym = 0.5f * (n.y0 + n.y1);
  out[0] = {{}, n.x0, xm, n.y0, ym};
  out[1] = {{}, xm, n.x1, n.y0, ym};
  out[2] = {{}, n.x0, xm, ym, n.y1};
  out[3] = {{}, xm, n.x1, ym, n.y1};
  for (const auto& kp : n.kps) {
    const int idx = (kp.pt.x < xm ? 0 : 1) + (kp.pt.y < ym ? 0 : 2);
    out[idx].kps.push_back(kp);
  }
}
}  // namespace

std::vector<cv::KeyPoint> distributeQuadtree(const std::vector<cv::KeyPoint>& keypoints, int min_x,
                                             int max_x, int min_y, int max_y, int target) {
  if (keypoints.empty() || target <= 0) return {};
  // Initial nodes: roughly square columns across the image.
  const float w = float(max_x - min_x), h = float(max_y - min_y);
  const int n_init = std::max(1, int(std::lround(w / std::max(h, 1.0f))));
  const float dx = w / n_init;
  std::list<QuadNode> nodes;
  for (int i = 0; i < n_init; ++i) {
    nodes.push_back({{}, min_x + dx * i, min_x + dx * (i + 1), float(min_y), float(max_y)});
  }
  for (const auto& kp : keypoints) {
    const int i = std::clamp(int((kp.pt.x - min_x) / dx), 0, n_init - 1);
    std::next(nodes.begin(), i)->kps.push_back(kp);
  }
  nodes.remove_if([](const QuadNode& n) { return n.kps.empty(); });

  bool finished = false;
  while (!finished) {
    const size_t before = nodes.size();
    std::vector<std::list<QuadNode>::iterator> expandable;
    for (auto it = nodes.begin(); it != nodes.end();) {
      if (it->leaf() || (it->x1 - it->x0) < 1.0f) {
        ++it;
        continue;
      }
      QuadNode children[4];
      splitNode(*it, children);
      for (auto& c : children) {
        if (c.kps.empty()) continue;
        nodes.push_front(std::move(c));
        if (!nodes.front().leaf()) expandable.push_back(nodes.begin());
      }
      it = nodes.erase(it);
    }
    if (int(nodes.size()) >= target || nodes.size() == before) {
      finished = true;
    } else if (int(nodes.size() + expandable.size() * 3) > target) {
      // Close to the target: split the most populated nodes first, one at a time.
      while (!finished) {
        const size_t prev = nodes.size();
        auto candidates = expandable;
        expandable.clear();
        std::stable_sort(candidates.begin(), candidates.end(), [](auto a, auto b) {
          if (a->kps.size() != b->kps.size()) return a->kps.size() > b->kps.size();
          if (a->x0 != b->x0) return a->x0 < b->x0;
          return a->y0 < b->y0;
        });
        for (auto it : candidates) {
          QuadNode children[4];
          splitNode(*it, children);
          for (auto& c : children) {
            if (c.kps.empty()) continue;
            nodes.push_front(std::move(c));
            if (!nodes.front().leaf() && (nodes.front().x1 - nodes.front().x0) >= 1.0f) {
              expandable.push_back(nodes.begin());
            }
          }
          nodes.erase(it);
          if (int(nodes.size()) >= target) break;
        }
        if (int(nodes.size()) >= target || nodes.size() == prev || expandable.empty()) finished = true;
      }
    }
  }
  std::vector<cv::KeyPoint> out;
  out.reserve(nodes.size());
  for (const auto& n : nodes) {
    const auto best = std::max_element(n.kps.begin(), n.kps.end(), [](const auto& a, const auto& b) {
      return a.response < b.response;
    });
    out.push_back(*best);
  }
  // Deterministic order independent of the list's insertion order.
  std::sort(out.begin(), out.end(), [](const cv::KeyPoint& a, const cv::KeyPoint& b) {
    return a.pt.y != b.pt.y ? a.pt.y < b.pt.y : a.pt.x < b.pt.x;
  });
  return out;
}

OrbExtractor::OrbExtractor(const OrbParams& params) : params_(params) {
  if (params_.features < 10) throw InputError("orb.features must be >= 10");
  if (!(params_.scale_factor > 1.0 && params_.scale_factor < 4.0)) {
    throw InputError("orb.scale_factor must be in (1, 4)");
  }
  if (params_.levels < 1 || params_.levels > 16) throw InputError("orb.levels must be in [1, 16]");
  if (params_.fast_threshold < 1 || params_.fast_min_threshold < 1 ||
      params_.fast_min_threshold > params_.fast_threshold) {
    throw InputError("orb: need 1 <= fast_min_threshold <= fast_threshold");
  }
  const int L = params_.levels;
  pyramid_ = ScalePyramid::make(L, params_.scale_factor);
  // Geometric share of features per level (more on the finer levels).
  const double f = 1.0 / params_.scale_factor;
  double per_level = params_.features * (1 - f) / (1 - std::pow(f, L));
  int total = 0;
  features_per_level_.resize(L);
  for (int l = 0; l < L - 1; ++l) {
    features_per_level_[l] = int(std::lround(per_level));
    total += features_per_level_[l];
    per_level *= f;
  }
  features_per_level_[L - 1] = std::max(params_.features - total, 0);

  // Circular patch for the intensity centroid.
  umax_.resize(kHalfPatch + 1);
  const int vmax = int(std::floor(kHalfPatch * std::sqrt(2.0) / 2 + 1));
  const int vmin = int(std::ceil(kHalfPatch * std::sqrt(2.0) / 2));
  const double hp2 = kHalfPatch * kHalfPatch;
  for (int v = 0; v <= vmax; ++v) umax_[v] = int(std::lround(std::sqrt(hp2 - v * v)));
  for (int v = kHalfPatch, v0 = 0; v >= vmin; --v) {
    while (umax_[v0] == umax_[v0 + 1]) ++v0;
    umax_[v] = v0;
    ++v0;
  }
  // OpenCV's ORB only computes the descriptors of our keypoints (its own pyramid, blurred).
  descriptor_ = cv::ORB::create(params_.features, float(params_.scale_factor), params_.levels,
                                kFastBorder, 0, 2, cv::ORB::FAST_SCORE, kPatchSize, params_.fast_threshold);
}

std::vector<cv::KeyPoint> OrbExtractor::detectCorners(const cv::Mat& img) const {
  const auto [min_x, min_y, max_x, max_y] = fastArea(img);
  if (max_x - min_x < kCellSize / 2 || max_y - min_y < kCellSize / 2) return {};
  // One FAST pass at the low threshold; a corner's response is the highest threshold at which
  // it is still a corner, so "response >= high threshold" selects the high-threshold corners.
  std::vector<cv::KeyPoint> all;
  cv::FAST(img(cv::Rect(min_x - 3, min_y - 3, max_x - min_x + 6, max_y - min_y + 6)), all,
           params_.fast_min_threshold, true);
  std::vector<cv::KeyPoint> inside;
  inside.reserve(all.size());
  for (auto& kp : all) {
    kp.pt.x += min_x - 3;
    kp.pt.y += min_y - 3;
    if (kp.pt.x < min_x || kp.pt.y < min_y || kp.pt.x >= max_x || kp.pt.y >= max_y) continue;
    inside.push_back(kp);
  }
  return inside;
}

std::vector<cv::KeyPoint> OrbExtractor::selectKeypoints(const cv::Mat& img, int level,
                                                        const std::vector<cv::KeyPoint>& all,
                                                        const cv::Mat& skip) const {
  const auto [min_x, min_y, max_x, max_y] = fastArea(img);
  if (all.empty()) return {};
  const int cols = std::max(1, (max_x - min_x) / kCellSize);
  const int rows = std::max(1, (max_y - min_y) / kCellSize);
  const float cell_w = float(max_x - min_x) / cols, cell_h = float(max_y - min_y) / rows;
  std::vector<std::vector<int>> cells(cols * rows);
  std::vector<char> cell_has_strong(cols * rows, 0);
  for (size_t k = 0; k < all.size(); ++k) {
    const auto& kp = all[k];
    if (!skip.empty()) {
      const float s = float(pyramid_.scales[level]);
      const cv::Point p0(std::min(skip.cols - 1, cvRound(kp.pt.x * s)), std::min(skip.rows - 1, cvRound(kp.pt.y * s)));
      if (skip.at<uchar>(p0)) continue;
    }
    const int cx = std::min(int((kp.pt.x - min_x) / cell_w), cols - 1);
    const int cy = std::min(int((kp.pt.y - min_y) / cell_h), rows - 1);
    cells[cy * cols + cx].push_back(int(k));
    if (kp.response >= params_.fast_threshold) cell_has_strong[cy * cols + cx] = 1;
  }
  std::vector<cv::KeyPoint> candidates;
  for (size_t c = 0; c < cells.size(); ++c) {
    for (int k : cells[c]) {
      if (!cell_has_strong[c] || all[k].response >= params_.fast_threshold) candidates.push_back(all[k]);
    }
  }
  auto kps = distributeQuadtree(candidates, min_x, max_x, min_y, max_y, features_per_level_[level]);
  // Orientation by the intensity centroid of the circular patch.
  const int step = int(img.step1());
  for (auto& kp : kps) {
    const uchar* center = img.ptr<uchar>(cvRound(kp.pt.y)) + cvRound(kp.pt.x);
    int m01 = 0, m10 = 0;
    for (int u = -kHalfPatch; u <= kHalfPatch; ++u) m10 += u * center[u];
    for (int v = 1; v <= kHalfPatch; ++v) {
      int v_sum = 0;
      const int d = umax_[v];
      for (int u = -d; u <= d; ++u) {
        const int plus = center[u + v * step], minus = center[u - v * step];
        v_sum += plus - minus;
        m10 += u * (plus + minus);
      }
      m01 += v * v_sum;
    }
    float angle = cv::fastAtan2(float(m01), float(m10));
    kp.angle = angle;
    kp.octave = level;
    kp.size = float(kPatchSize * pyramid_.scales[level]);
  }
  return kps;
}

cv::Mat OrbExtractor::describeLevel(const cv::Mat& level_image, const std::vector<cv::KeyPoint>& kps) const {
  if (kps.empty()) return cv::Mat(0, 32, CV_8U);
  // cv::ORB on the level image itself, the keypoints as its level 0: the same descriptors as from
  // the full image at their octave (it would resize the image to that level exactly as extract()
  // did, then blur it), without building the pyramid again.
  // It blurs and pads all of the image it is given, so it gets only the part around the
  // keypoints: an ROI is padded from the pixels around it, and with a margin wider than the
  // rotated patch (ceil(15 sqrt 2) = 22 px) every pixel a descriptor reads is blurred from the
  // same neighbours as in the whole image, so the descriptors are the same. (Matters for the
  // refill, whose new keypoints lie outside the boxes.)
  float x0 = kps[0].pt.x, y0 = kps[0].pt.y, x1 = x0, y1 = y0;
  for (const auto& kp : kps) {
    x0 = std::min(x0, kp.pt.x), y0 = std::min(y0, kp.pt.y);
    x1 = std::max(x1, kp.pt.x), y1 = std::max(y1, kp.pt.y);
  }
  constexpr int kMargin = kPatchSize + 1;
  const cv::Point tl(std::max(0, int(std::floor(x0)) - kMargin), std::max(0, int(std::floor(y0)) - kMargin));
  const cv::Point br(std::min(level_image.cols, int(std::ceil(x1)) + kMargin + 1),
                     std::min(level_image.rows, int(std::ceil(y1)) + kMargin + 1));
  std::vector<cv::KeyPoint> at_level = kps;
  for (auto& kp : at_level) {
    kp.octave = 0;
    kp.pt -= cv::Point2f(float(tl.x), float(tl.y));  // exact: an integer shift of a smaller float
  }
  cv::Mat descriptors;
  descriptor_->compute(level_image(cv::Rect(tl, br)), at_level, descriptors);
  if (at_level.size() != kps.size()) {
    throw std::logic_error("ORB descriptor computation dropped keypoints");  // border mismatch
  }
  return descriptors;
}

void OrbExtractor::toLevelZero(std::vector<cv::KeyPoint>& kps, int level) const {
  for (auto& kp : kps) kp.pt *= float(pyramid_.scales[level]);
}

void OrbExtractor::checkInputs(const cv::Mat& gray, const cv::Mat& skip) const {
  if (gray.empty() || gray.type() != CV_8UC1) throw InputError("ORB extraction needs an 8-bit grey image");
  if (!skip.empty() && (skip.type() != CV_8UC1 || skip.size() != gray.size())) {
    throw InputError("ORB extraction: the skip mask must be 8-bit and of the image's size");
  }
}


OrbFeatures OrbExtractor::extract(const cv::Mat& gray, const cv::Mat& skip, OrbDetections* detections) const {
  checkInputs(gray, skip);
  OrbFeatures out;
  if (detections) *detections = {};
  std::vector<cv::Mat> descriptors;
  cv::Mat level_img = gray;
  for (int l = 0; l < params_.levels; ++l) {
    if (l > 0) {
      const cv::Size sz(cvRound(gray.cols * pyramid_.inv_scales[l]), cvRound(gray.rows * pyramid_.inv_scales[l]));
      cv::Mat next;
      cv::resize(level_img, next, sz, 0, 0, cv::INTER_LINEAR_EXACT);
      level_img = next;
    }
    auto corners = detectCorners(level_img);
    auto kps = selectKeypoints(level_img, l, corners, skip);
    descriptors.push_back(describeLevel(level_img, kps));
    toLevelZero(kps, l);
    out.keypoints.insert(out.keypoints.end(), kps.begin(), kps.end());
    if (detections) {
      detections->levels.push_back(level_img);
      detections->corners.push_back(std::move(corners));
    }
  }
  out.descriptors = stackDescriptors(descriptors);
  return out;
}

OrbFeatures OrbExtractor::extractAgain(const OrbDetections& detections, const cv::Mat& gray, const cv::Mat& skip,
                                       const OrbFeatures& previous) const {
  checkInputs(gray, skip);
  if (int(detections.levels.size()) != params_.levels || detections.corners.size() != detections.levels.size() ||
      detections.levels[0].size() != gray.size()) {
    throw InputError("ORB extraction: the detections are not of this image");
  }
  if (previous.descriptors.rows != int(previous.keypoints.size())) {
    throw InputError("ORB extraction: the previous features need one descriptor per keypoint");
  }
  // Keypoints are identified by level and position: the same corner gives the same keypoint.
  const auto key = [](const cv::Point2f& p) {
    uint32_t x, y;
    std::memcpy(&x, &p.x, sizeof x);
    std::memcpy(&y, &p.y, sizeof y);
    return (uint64_t(x) << 32) | y;
  };
  std::vector<std::unordered_map<uint64_t, int>> known(params_.levels);  // per level: position -> row
  for (size_t i = 0; i < previous.keypoints.size(); ++i) {
    const auto& kp = previous.keypoints[i];
    if (kp.octave >= 0 && kp.octave < params_.levels) known[kp.octave].emplace(key(kp.pt), int(i));
  }
  OrbFeatures out;
  std::vector<cv::Mat> rows;
  for (int l = 0; l < params_.levels; ++l) {
    const auto kps = selectKeypoints(detections.levels[l], l, detections.corners[l], skip);
    auto at0 = kps;
    toLevelZero(at0, l);
    std::vector<int> reused;          // per keypoint: row of previous.descriptors, or -1
    std::vector<cv::KeyPoint> fresh;  // the others, described here (level coordinates)
    for (size_t k = 0; k < kps.size(); ++k) {
      const auto it = known[l].find(key(at0[k].pt));
      reused.push_back(it == known[l].end() ? -1 : it->second);
      if (it == known[l].end()) fresh.push_back(kps[k]);
    }
    const cv::Mat fresh_descriptors = describeLevel(detections.levels[l], fresh);
    for (size_t k = 0, next_fresh = 0; k < kps.size(); ++k) {
      rows.push_back(reused[k] >= 0 ? previous.descriptors.row(reused[k]) : fresh_descriptors.row(int(next_fresh++)));
    }
    out.keypoints.insert(out.keypoints.end(), at0.begin(), at0.end());
  }
  out.descriptors = stackDescriptors(rows);
  return out;
}

}  // namespace tkgslam::feature
