#include "tkgslam/augment/SequenceAugmenter.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <random>

#include <fmt/format.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "tkgslam/common/Error.h"
#include "tkgslam/eval/Association.h"
#include "tkgslam/io/OutputFile.h"
#include "tkgslam/io/OutputFolder.h"

namespace fs = std::filesystem;

namespace tkgslam::augment {

namespace {

// A person walking a smooth closed path in the world: an ellipse-like sway around a centre in
// front of the first camera, x (sideways) and z (depth) oscillating at different rates.
struct Walker {
  const PersonCutout* cutout;
  Vec3 centre_c0;    // path centre in the first camera's frame
  double amp_x, amp_z, omega, phase;
  double height_m;   // physical height, consistent with its on-screen size
  Pose T_w_c0;

  Vec3 positionWorld(double t) const {
    const Vec3 p(centre_c0.x() + amp_x * std::sin(omega * t + phase), centre_c0.y(),
                 centre_c0.z() + amp_z * std::sin(0.5 * omega * t + 2 * phase));
    return T_w_c0 * p;
  }
};

void writeImage(const fs::path& p, const cv::Mat& img, const std::vector<int>& params = {}) {
  if (!cv::imwrite(p.string(), img, params)) throw InputError(fmt::format("cannot write '{}'", p.string()));
}

}  // namespace

void checkAugmentOptions(const AugmentOptions& o) {
  if (o.people < 1 || !(o.min_size > 0 && o.min_size <= o.max_size && o.max_size <= 1.5)) {
    throw InputError(fmt::format("augment: need people >= 1 and 0 < min_size <= max_size <= 1.5 (got --count {}, --min-size {}, --max-size {})",
                                 o.people, o.min_size, o.max_size));
  }
}

void checkGroundTruthCovers(const io::TumDataset& ds, const std::vector<io::TrajectoryEntry>& gt, int max_frames) {
  if (gt.size() < 2) throw InputError("augment: the dataset needs a ground-truth trajectory");
  std::vector<double> gt_stamps;
  for (const auto& e : gt) gt_stamps.push_back(e.timestamp);
  const int n = max_frames > 0 ? std::min(max_frames, ds.size()) : ds.size();
  for (int i = 0; i < n; ++i) {
    const double t = ds.timestamp(i);
    const double gap = std::abs(gt_stamps[size_t(eval::findClosestIndex(gt_stamps, t))] - t);
    if (gap > kMaxGroundTruthGap) {
      throw InputError(fmt::format("augment: frame {} ({:.6f} s) has no ground-truth pose within {} s (the nearest is "
                                   "{:.3f} s away); the ground truth must cover the frames, in seconds",
                                   i, t, kMaxGroundTruthGap, gap));
    }
  }
}

AugmentStats augmentSequence(const io::TumDataset& ds, const std::vector<io::TrajectoryEntry>& gt,
                             const std::vector<PersonCutout>& cutouts, const camera::PinholeCamera& cam,
                             double depth_factor, const std::string& out_dir, const AugmentOptions& o,
                             const AugmentProgress& progress) {
  if (cutouts.empty()) throw InputError("augment: no person cut-outs");
  checkAugmentOptions(o);
  std::vector<double> gt_stamps;
  for (const auto& e : gt) gt_stamps.push_back(e.timestamp);
  auto gtPose = [&](double t) { return gt[eval::findClosestIndex(gt_stamps, t)].pose(); };  // T_wc
  const int n = o.max_frames > 0 ? std::min(o.max_frames, ds.size()) : ds.size();
  checkGroundTruthCovers(ds, gt, o.max_frames);
  const fs::path out(out_dir);
  for (const char* sub : {"rgb", "depth", "masks"}) io::createOutputFolder((out / sub).string());
  std::mt19937_64 rng(o.seed);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  const double t0 = ds.timestamp(0);
  const Pose T_w_c0 = gtPose(t0);

  AugmentStats stats;
  std::vector<Walker> walkers;
  for (int k = 0; k < o.people; ++k) {
    Walker w;
    const size_t which = size_t(U(rng) * cutouts.size()) % cutouts.size();
    w.cutout = &cutouts[which];
    stats.person_cutouts.push_back(int(which));
    const double z = 0.4 + 0.2 * U(rng);  // in front of the desk the camera looks at
    const double size = o.min_size + (o.max_size - o.min_size) * U(rng);
    w.height_m = size * cam.height() * z / cam.fy();
    // Keep the whole body in view most of the time: sway between the image borders.
    const double half_width_m = 0.5 * cam.width() * z / cam.fx();
    const double body_half_m = 0.5 * w.height_m * w.cutout->bgr.cols / w.cutout->bgr.rows;
    const double room = std::max(0.05 * half_width_m, half_width_m - body_half_m);
    const double centre_y = ((cam.height() / 2.0 - cam.cy()) / cam.fy()) * z;  // body centred vertically
    w.centre_c0 = Vec3((U(rng) - 0.5) * 0.5 * room, centre_y, z);
    w.amp_x = room * (0.5 + 0.5 * U(rng));
    w.amp_z = 0.1 * z * U(rng);
    w.omega = o.speed / std::max(w.amp_x, 1e-3);  // peak sideways speed = amp * omega
    w.phase = 2 * M_PI * U(rng);
    w.T_w_c0 = T_w_c0;
    walkers.push_back(w);
  }

  // The lists are written when every image is: a failed run leaves no list naming missing images.
  std::string rgb_list = fmt::format("# color images (tkgslam augment, seed {})\n# timestamp filename\n", o.seed);
  std::string depth_list = "# depth maps (tkgslam augment)\n# timestamp filename\n";
  std::string boxes = "# timestamp person x y w h (raw pixels; ground truth of the composited people)\n";
  for (int i = 0; i < n; ++i) {
    auto frame = ds.load(i);
    cv::Mat bgr = frame.bgr.clone();
    cv::Mat depth = frame.depth_m.clone();
    cv::Mat dyn_mask = cv::Mat::zeros(bgr.size(), CV_8U);
    const Pose T_cw = gtPose(frame.timestamp).inverse();
    const double t = frame.timestamp - t0;
    // Far people first so nearer ones are drawn over them.
    std::vector<std::pair<double, int>> order;
    for (int k = 0; k < o.people; ++k) order.emplace_back(-(T_cw * walkers[k].positionWorld(t)).z(), k);
    std::sort(order.begin(), order.end());
    cv::Mat box_union = cv::Mat::zeros(bgr.size(), CV_8U);
    for (const auto& [neg_z, k] : order) {
      const Walker& w = walkers[k];
      const Vec3 pc = T_cw * w.positionWorld(t);
      if (pc.z() < 0.15) continue;
      const double h_px = cam.fy() * w.height_m / pc.z();
      const double w_px = h_px * w.cutout->bgr.cols / w.cutout->bgr.rows;
      const Vec2 c = cam.distort(cam.project(pc));
      const cv::Rect target(int(std::lround(c.x() - w_px / 2)), int(std::lround(c.y() - h_px / 2)),
                            std::max(1, int(std::lround(w_px))), std::max(1, int(std::lround(h_px))));
      const cv::Rect visible = target & cv::Rect(0, 0, bgr.cols, bgr.rows);
      if (visible.area() <= 0) continue;
      cv::Mat sprite, sprite_mask;
      cv::resize(w.cutout->bgr, sprite, target.size(), 0, 0, cv::INTER_AREA);
      cv::resize(w.cutout->mask, sprite_mask, target.size(), 0, 0, cv::INTER_NEAREST);
      const cv::Rect src = visible - target.tl();
      const float z = float(pc.z());
      int drawn = 0;
      cv::Rect drawn_box;
      for (int y = 0; y < visible.height; ++y) {
        for (int x = 0; x < visible.width; ++x) {
          if (!sprite_mask.at<uchar>(src.y + y, src.x + x)) continue;
          const int u = visible.x + x, v = visible.y + y;
          float& d = depth.at<float>(v, u);
          if (d > 0 && d <= z) continue;  // the background is nearer here: the person is hidden
          d = z;
          bgr.at<cv::Vec3b>(v, u) = sprite.at<cv::Vec3b>(src.y + y, src.x + x);
          dyn_mask.at<uchar>(v, u) = 255;
          drawn_box = drawn++ ? (drawn_box | cv::Rect(u, v, 1, 1)) : cv::Rect(u, v, 1, 1);
        }
      }
      if (drawn > 0) {
        boxes += fmt::format("{:.6f} {} {} {} {} {}\n", frame.timestamp, k, drawn_box.x, drawn_box.y,
                             drawn_box.width, drawn_box.height);
        box_union(drawn_box).setTo(255);
      }
    }
    if (o.blur_probability > 0 && U(rng) < o.blur_probability) {
      // Strong motion blur on the colour image (camera shake), or on the people only (fast
      // walkers): the detector tends to miss them.
      const int len = std::max(3, o.blur_kernel | 1);
      cv::Mat kernel = cv::Mat::zeros(len, len, CV_32F);
      const double angle = M_PI * U(rng);
      cv::line(kernel, cv::Point(int(len / 2 - std::cos(angle) * len / 2), int(len / 2 - std::sin(angle) * len / 2)),
               cv::Point(int(len / 2 + std::cos(angle) * len / 2), int(len / 2 + std::sin(angle) * len / 2)),
               cv::Scalar(1.0), 1);
      kernel /= cv::sum(kernel)[0];
      if (o.blur_people_only) {
        cv::Mat blurred, region;
        cv::filter2D(bgr, blurred, -1, kernel);
        // The smear reaches past the person's outline by half the kernel.
        cv::dilate(dyn_mask, region, cv::getStructuringElement(cv::MORPH_ELLIPSE, cv::Size(len / 2 | 1, len / 2 | 1)));
        blurred.copyTo(bgr, region);
      } else {
        cv::filter2D(bgr, bgr, -1, kernel);
      }
      ++stats.blurred;
    }
    const std::string stamp = fmt::format("{:.6f}", frame.timestamp);
    const std::string dstamp = fmt::format("{:.6f}", ds.entry(i).depth_timestamp);
    writeImage(out / "rgb" / (stamp + ".jpg"), bgr, {cv::IMWRITE_JPEG_QUALITY, o.jpeg_quality});
    cv::Mat depth16;
    depth.convertTo(depth16, CV_16U, depth_factor);
    writeImage(out / "depth" / (dstamp + ".png"), depth16);
    writeImage(out / "masks" / (stamp + ".png"), dyn_mask);
    rgb_list += stamp + " rgb/" + stamp + ".jpg\n";
    depth_list += dstamp + " depth/" + dstamp + ".png\n";
    const double coverage = double(cv::countNonZero(dyn_mask)) / dyn_mask.total();
    const double ratio = double(cv::countNonZero(box_union)) / box_union.total();
    stats.mean_coverage += coverage;
    stats.max_coverage = std::max(stats.max_coverage, coverage);
    stats.mean_box_ratio += ratio;
    stats.frames_ratio_over_07 += ratio >= 0.7;
    ++stats.frames;
    if (progress) progress(i + 1, n);
  }
  if (stats.frames > 0) {
    stats.mean_coverage /= stats.frames;
    stats.mean_box_ratio /= stats.frames;
  }
  io::writeOutputFile((out / "rgb.txt").string(), "image list", rgb_list);
  io::writeOutputFile((out / "depth.txt").string(), "image list", depth_list);
  io::writeOutputFile((out / "boxes.txt").string(), "box list", boxes);
  if (const auto g = ds.groundTruthPath()) {
    std::error_code ec;
    fs::copy_file(*g, out / "groundtruth.txt", fs::copy_options::overwrite_existing, ec);
    if (ec) throw InputError(fmt::format("cannot write '{}': {}", (out / "groundtruth.txt").string(), ec.message()));
  }
  return stats;
}

}  // namespace tkgslam::augment
