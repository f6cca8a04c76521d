#include "tkgslam/dynamic/DynamicFilter.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include <opencv2/imgproc.hpp>

namespace tkgslam::dynamic {

bool inMask(const cv::Mat& mask, const cv::Point2f& p) {
  const int u = cvRound(p.x), v = cvRound(p.y);
  return u >= 0 && v >= 0 && u < mask.cols && v < mask.rows && mask.at<uchar>(v, u);
}

namespace {
// The pixels a box widened by `margin` x its size on each side covers (may reach outside the image).
cv::Rect rasterRect(const cv::Rect2f& box, double margin) {
  const float mx = float(margin) * box.width, my = float(margin) * box.height;
  return cv::Rect(cv::Point(int(std::floor(box.x - mx)), int(std::floor(box.y - my))),
                  cv::Point(int(std::ceil(box.br().x + mx)), int(std::ceil(box.br().y + my))));
}

// The object's pixels in `around` (full resolution, 255) by GrabCut on a quarter-size crop, seeded
// by depth (see objectMaskInBoxes). Empty when the seeds lack one side (GrabCut needs both).
cv::Mat colourObject(const cv::Rect2f& box, const cv::Rect& around, const cv::Mat& bgr, const cv::Mat& depth_m,
                     float median, float farthest) {
  constexpr double kScale = 0.25;
  constexpr float kObjectBand = 0.03f;  // m around the median: certainly the object
  const cv::Rect frame(0, 0, bgr.cols, bgr.rows);
  const cv::Rect crop = rasterRect(box, 0.15) & frame;
  const cv::Size small(std::max(1, int(crop.width * kScale)), std::max(1, int(crop.height * kScale)));
  if (small.width < 4 || small.height < 4) return {};
  cv::Mat colour, depth;
  cv::resize(bgr(crop), colour, small, 0, 0, cv::INTER_AREA);
  cv::resize(depth_m(crop), depth, small, 0, 0, cv::INTER_NEAREST);
  const cv::Rect2f in_box((box.x - crop.x) * small.width / crop.width, (box.y - crop.y) * small.height / crop.height,
                          box.width * small.width / crop.width, box.height * small.height / crop.height);
  cv::Mat seeds(small, CV_8U);
  for (int v = 0; v < small.height; ++v) {
    const float* z = depth.ptr<float>(v);
    uchar* out = seeds.ptr<uchar>(v);
    for (int u = 0; u < small.width; ++u) {
      if (z[u] > farthest) {
        out[u] = cv::GC_BGD;
      } else if (!in_box.contains(cv::Point2f(u + 0.5f, v + 0.5f))) {
        out[u] = z[u] > 0 ? cv::GC_PR_BGD : cv::GC_BGD;
      } else {
        out[u] = z[u] > 0 && std::abs(z[u] - median) < kObjectBand ? cv::GC_FGD : cv::GC_PR_FGD;
      }
    }
  }
  const cv::Mat is_object = seeds & 1;  // GC_FGD and GC_PR_FGD are the odd labels
  const int object_seeds = cv::countNonZero(is_object);
  // GrabCut fits 5-component colour models to each side by k-means: it needs samples of both.
  constexpr int kMinSeeds = 16;
  if (object_seeds < kMinSeeds || int(seeds.total()) - object_seeds < kMinSeeds) return {};
  // The k-means draws from the thread's RNG: seed it so that runs repeat, and restore it.
  const uint64 saved = cv::theRNG().state;
  cv::theRNG().state = 0x7E57ULL;
  bool segmented = true;
  cv::Mat bgd_model, fgd_model;
  try {
    cv::grabCut(colour, seeds, cv::Rect(), bgd_model, fgd_model, 2, cv::GC_INIT_WITH_MASK);
  } catch (const cv::Exception&) {  // e.g. too few distinct colours for the models: use depth alone
    segmented = false;
  }
  cv::theRNG().state = saved;
  if (!segmented) return {};
  cv::Mat object_small = (seeds & 1) * 255;
  cv::Mat object = cv::Mat::zeros(around.size(), CV_8U);
  const cv::Rect shared = crop & around;
  cv::Mat object_crop;
  cv::resize(object_small, object_crop, crop.size(), 0, 0, cv::INTER_NEAREST);
  object_crop(shared - crop.tl()).copyTo(object(shared - around.tl()));
  return object;
}
/// floodFill's mask: 0 inside `region` (where growing may go), 1 elsewhere, with the 1-pixel border.
cv::Mat floodBarrier(const cv::Mat& region) {
  cv::Mat flood_mask(region.rows + 2, region.cols + 2, CV_8U, cv::Scalar(1));
  flood_mask(cv::Rect(1, 1, region.cols, region.rows)).setTo(0, region);
  return flood_mask;
}

// The object's pixels in `around` (255): the region of log-depth steps <= log(1 + step) grown from
// the pixels of `inner` (the box's central half) near the median, within `farthest`; plus what is
// nearer than the median or has no depth (see objectMaskInBoxes).
cv::Mat regionObject(const cv::Rect& inner, const cv::Rect& around, const cv::Mat& depth_m, float median, float farthest,
                     double step) {
  const cv::Mat z = depth_m(around);
  cv::Mat log_z;
  z.copyTo(log_z);
  const cv::Mat has_depth = z > 0;
  log_z.setTo(1.0f, ~has_depth);  // any value: these pixels are barriers
  cv::log(log_z, log_z);
  cv::Mat flood_mask = floodBarrier(has_depth & (z <= farthest));
  const double log_step = std::log1p(step);
  const float seed_lo = median / float(1 + step), seed_hi = median * float(1 + step);
  const int flags = 4 | cv::FLOODFILL_MASK_ONLY | (255 << 8);
  const cv::Rect seeds = inner & around;
  for (int v = seeds.y; v < seeds.br().y; ++v) {
    const float* row = depth_m.ptr<float>(v);
    for (int u = seeds.x; u < seeds.br().x; ++u) {
      if (row[u] < seed_lo || row[u] > seed_hi) continue;
      const cv::Point s(u - around.x, v - around.y);
      if (flood_mask.at<uchar>(s.y + 1, s.x + 1)) continue;  // already grown (or a barrier)
      cv::floodFill(log_z, flood_mask, s, cv::Scalar(), nullptr, cv::Scalar(log_step), cv::Scalar(log_step), flags);
    }
  }
  cv::Mat object = flood_mask(cv::Rect(1, 1, around.width, around.height)) == 255;
  object |= z <= median;  // nearer, and no depth (0)
  return object;
}
}  // namespace

BoxMask rasterizeBoxes(const std::vector<Detection>& boxes, cv::Size image, double margin) {
  BoxMask m;
  m.mask = cv::Mat::zeros(image, CV_8U);
  const cv::Rect frame(0, 0, image.width, image.height);
  for (const auto& d : boxes) {
    const cv::Rect r = rasterRect(d.box, margin) & frame;
    if (r.area() > 0) m.mask(r).setTo(255);
  }
  m.ratio = image.area() > 0 ? double(cv::countNonZero(m.mask)) / image.area() : 0.0;
  return m;
}

BoxMask objectMaskInBoxes(const std::vector<Detection>& boxes, const cv::Mat& bgr, const cv::Mat& depth_m,
                          double margin, const ObjectMaskParams& params) {
  CV_Assert(depth_m.type() == CV_32F);
  CV_Assert(!params.colour || (bgr.type() == CV_8UC3 && bgr.size() == depth_m.size()));
  CV_Assert(params.behind_per_size <= 0 || params.focal_px > 0);
  BoxMask m;
  m.mask = cv::Mat::zeros(depth_m.size(), CV_8U);
  const cv::Rect frame(0, 0, depth_m.cols, depth_m.rows);
  const int r = std::max(0, params.radius);
  const cv::Mat kernel = cv::getStructuringElement(cv::MORPH_RECT, cv::Size(2 * r + 1, 2 * r + 1));
  std::vector<float> centre;
  for (const auto& d : boxes) {
    const cv::Rect widened = rasterRect(d.box, margin) & frame;
    if (widened.area() <= 0) continue;
    const cv::Rect inner = rasterRect(d.box, -0.25) & frame;  // the box's central half
    centre.clear();
    for (int v = inner.y; v < inner.br().y; ++v) {
      const float* row = depth_m.ptr<float>(v);
      for (int u = inner.x; u < inner.br().x; ++u) {
        if (row[u] > 0) centre.push_back(row[u]);
      }
    }
    cv::Mat out = m.mask(widened);
    if (centre.empty()) {
      out.setTo(255);
      continue;
    }
    auto mid = centre.begin() + centre.size() / 2;
    std::nth_element(centre.begin(), mid, centre.end());
    const double behind = params.behind_per_size > 0
                              ? params.behind_per_size * std::max(d.box.width, d.box.height) * *mid / params.focal_px
                              : params.behind;
    const float farthest = *mid + float(behind);
    // The object's pixels, in the widened box plus the radius (so the dilation near the box's edge
    // sees them), then dilated and cut back to the widened box.
    const cv::Rect around = cv::Rect(widened.x - r, widened.y - r, widened.width + 2 * r, widened.height + 2 * r) & frame;
    cv::Mat object;
    if (params.region) {
      object = regionObject(inner, around, depth_m, *mid, farthest, params.region_step);
    } else if (params.colour) {
      object = colourObject(d.box, around, bgr, depth_m, *mid, farthest);
    }
    if (object.empty()) cv::compare(depth_m(around), farthest, object, cv::CMP_LE);  // no depth (0) too
    if (r > 0) cv::dilate(object, object, kernel);
    out |= object(widened - around.tl());
  }
  m.ratio = frame.area() > 0 ? double(cv::countNonZero(m.mask)) / frame.area() : 0.0;
  return m;
}

BoxMask dynamicMask(const std::vector<Detection>& boxes, const cv::Mat& bgr, const cv::Mat& depth_m, double margin,
                    const ObjectMaskParams* object) {
  BoxMask whole = rasterizeBoxes(boxes, bgr.empty() ? depth_m.size() : bgr.size(), margin);
  if (!object) return whole;
  BoxMask m = objectMaskInBoxes(boxes, bgr, depth_m, margin, *object);
  m.ratio = whole.ratio;
  return m;
}

int excludeKeypointsInMask(data::FrameFeatures& f, const cv::Mat& mask) {
  int n = 0;
  for (int i = 0; i < f.size(); ++i) {
    if (!f.excluded[i] && inMask(mask, f.raw[i].pt)) {
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

namespace {
/// Reference keypoints (world points seen by the reference keyframes) that project into `region`
/// of the current frame and are hidden there behind nearer structure: each one is evidence of
/// something that moved in front of the static scene. Returns the evidence pixels, moved to the
/// nearest surface in the patch (the occluder, where a region is grown from). `consistent`, if
/// given, receives the pixels of the reference points found where they were (not hidden).
std::vector<cv::Point> findOcclusionEvidence(const Pose& T_cw, const cv::Mat& depth_m, const cv::Mat& region,
                                             const std::vector<ReferenceView>& refs, const camera::PinholeCamera& cam,
                                             const GeometryParams& p, int& projected,
                                             std::vector<cv::Point>* consistent = nullptr) {
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
      if (!region.at<uchar>(v, u)) continue;  // only the region is in question
      ++projected;
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
      if (z_best <= 0 || z_proj - z_best <= p.occlusion_threshold) {
        if (consistent && count > 0) consistent->emplace_back(u, v);
        continue;
      }
      const double mean = sum / count;
      const double var = std::max(0.0, sum_sq / count - mean * mean);
      if (std::sqrt(var) > p.max_patch_std) continue;  // complex occlusion at an edge: static
      // Seed at the nearest surface in the patch (the occluder), not at a background pixel.
      cv::Point best(u, v);
      float z_min = std::numeric_limits<float>::max();
      for (int dv = -p.patch_radius; dv <= p.patch_radius; ++dv) {
        for (int du = -p.patch_radius; du <= p.patch_radius; ++du) {
          const cv::Point q(u + du, v + dv);
          if (q.x < 0 || q.y < 0 || q.x >= depth_m.cols || q.y >= depth_m.rows || !region.at<uchar>(q)) continue;
          const float z = depth_m.at<float>(q);
          if (z > 0 && z < z_min) z_min = z, best = q;
        }
      }
      if (z_min < std::numeric_limits<float>::max()) seeds.push_back(best);
    }
  }
  return seeds;
}
}  // namespace

GeometryResult checkMultiViewGeometry(const Pose& T_cw, const cv::Mat& depth_m, const cv::Mat& box_mask,
                                      const std::vector<ReferenceView>& refs, const camera::PinholeCamera& cam,
                                      const GeometryParams& p) {
  GeometryResult result;
  result.dynamic_region = cv::Mat::zeros(depth_m.size(), CV_8U);
  const auto seeds = findOcclusionEvidence(T_cw, depth_m, box_mask, refs, cam, p, result.projected);
  result.evidence = int(seeds.size());
  if (seeds.empty()) return result;
  // Grow depth-consistent regions from the evidence, confined to the boxes.
  cv::Mat flood_mask = floodBarrier(box_mask);
  const int flags = 4 | cv::FLOODFILL_MASK_ONLY | (255 << 8);
  cv::Mat depth = depth_m.clone();  // floodFill requires a writable image even in mask-only mode
  for (const auto& s : seeds) {
    if (flood_mask.at<uchar>(s.y + 1, s.x + 1)) continue;  // already grown
    cv::floodFill(depth, flood_mask, s, cv::Scalar(), nullptr, cv::Scalar(p.region_depth_step),
                  cv::Scalar(p.region_depth_step), flags);
  }
  // Region pixels were marked 255 (fill value); barriers were 1.
  cv::Mat inner = flood_mask(cv::Rect(1, 1, depth_m.cols, depth_m.rows));
  result.dynamic_region = (inner == 255);
  return result;
}

GeometryResult findUnboxedMovers(const Pose& T_cw, const cv::Mat& depth_m, const cv::Mat& box_mask,
                                 const std::vector<ReferenceView>& refs, const camera::PinholeCamera& cam,
                                 const GeometryParams& p) {
  GeometryResult result;
  result.dynamic_region = cv::Mat::zeros(depth_m.size(), CV_8U);
  const cv::Mat outside = box_mask.empty() ? cv::Mat(depth_m.size(), CV_8U, cv::Scalar(255)) : (box_mask == 0);
  std::vector<cv::Point> consistent;
  const auto seeds = findOcclusionEvidence(T_cw, depth_m, outside, refs, cam, p, result.projected, &consistent);
  result.evidence = int(seeds.size());
  if (int(seeds.size()) < p.unboxed_min_evidence) return result;
  // One region per connected surface within +-unboxed_depth_range of its seed's depth (a fixed
  // range, not a step: nothing confines the growth here, and a step would follow a floor or a
  // wall the mover stands on). A region is a mover only with enough evidence of its own, and only
  // if most of what the keyframes saw there is hidden: on a static surface a few edge points are.
  cv::Mat flood_mask = floodBarrier(outside);
  cv::Mat depth = depth_m.clone();
  const double range = p.unboxed_depth_range;
  int label = 2;  // floodFill marks with 2, 3, ... (1 = barrier); at most 253 regions
  std::vector<int> votes;
  for (const auto& s : seeds) {
    uchar& here = flood_mask.at<uchar>(s.y + 1, s.x + 1);
    if (here == 1) continue;
    if (here == 0) {
      if (label > 254) continue;
      const int flags = 4 | cv::FLOODFILL_MASK_ONLY | cv::FLOODFILL_FIXED_RANGE | (label << 8);
      cv::floodFill(depth, flood_mask, s, cv::Scalar(), nullptr, cv::Scalar(range), cv::Scalar(range), flags);
      votes.push_back(0);
      ++label;
    }
    ++votes[size_t(here - 2)];
  }
  cv::Mat inner = flood_mask(cv::Rect(1, 1, depth_m.cols, depth_m.rows));
  std::vector<int> seen(votes.size(), 0);
  for (const auto& q : consistent) {
    const int l = inner.at<uchar>(q);
    if (l >= 2 && l < label) ++seen[size_t(l - 2)];
  }
  // Accepted regions may run on into static surfaces within the depth range that touch the mover:
  // in them, the region is grown again from the evidence with the neighbour-step rule of the
  // in-box check, which stops where the depth jumps.
  cv::Mat barrier(flood_mask.size(), CV_8U, cv::Scalar(1));
  cv::Mat barrier_inner = barrier(cv::Rect(1, 1, depth_m.cols, depth_m.rows));
  bool any = false;
  for (size_t k = 0; k < votes.size(); ++k) {
    if (votes[k] >= p.unboxed_min_evidence && votes[k] >= p.unboxed_min_hidden * (votes[k] + seen[k])) {
      barrier_inner.setTo(0, inner == int(k + 2));
      any = true;
    }
  }
  if (!any) return result;
  const int flags = 4 | cv::FLOODFILL_MASK_ONLY | (255 << 8);
  for (const auto& s : seeds) {
    if (barrier.at<uchar>(s.y + 1, s.x + 1)) continue;  // not in an accepted region, or grown
    cv::floodFill(depth, barrier, s, cv::Scalar(), nullptr, cv::Scalar(p.region_depth_step),
                  cv::Scalar(p.region_depth_step), flags);
  }
  result.dynamic_region = (barrier_inner == 255);
  return result;
}

int readmitStaticKeypoints(data::FrameFeatures& f, const cv::Mat& box_mask, const cv::Mat& dynamic_region,
                           const cv::Mat& depth_m, const GeometryParams& p) {
  // Nearest depth within the radius around every pixel (no depth counts as far).
  cv::Mat nearest;
  if (p.occluder_radius > 0 && !depth_m.empty()) {
    cv::Mat far = depth_m.clone();
    far.setTo(std::numeric_limits<float>::max(), depth_m <= 0);
    const int side = 2 * p.occluder_radius + 1;
    cv::erode(far, nearest, cv::getStructuringElement(cv::MORPH_RECT, cv::Size(side, side)));
  }
  int n = 0;
  for (int i = 0; i < f.size(); ++i) {
    if (!f.excluded[i] || !inMask(box_mask, f.raw[i].pt)) continue;
    if (!dynamic_region.empty() && inMask(dynamic_region, f.raw[i].pt)) continue;
    const cv::Point q(cvRound(f.raw[i].pt.x), cvRound(f.raw[i].pt.y));
    if (!nearest.empty() && f.hasDepth(i) && q.inside(cv::Rect(0, 0, nearest.cols, nearest.rows)) &&
        nearest.at<float>(q) < f.depth[i] - p.occluder_depth) {
      continue;  // on an occluding outline, see GeometryParams::occluder_radius
    }
    f.excluded[i] = 0;
    ++n;
  }
  return n;
}

}  // namespace tkgslam::dynamic
