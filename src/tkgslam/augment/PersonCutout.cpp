#include "tkgslam/augment/PersonCutout.h"

#include <algorithm>
#include <filesystem>

#include <fmt/format.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "tkgslam/common/Error.h"

namespace tkgslam::augment {

cv::Mat segmentInBox(const cv::Mat& bgr, const cv::Rect& box) {
  // Work on the box plus a margin so GrabCut has background to learn from.
  const cv::Rect frame(0, 0, bgr.cols, bgr.rows);
  const int mx = box.width / 4, my = box.height / 8;
  const cv::Rect roi = cv::Rect(box.x - mx, box.y - my, box.width + 2 * mx, box.height + 2 * my) & frame;
  cv::Mat crop = bgr(roi).clone();
  cv::Mat gc_mask(crop.size(), CV_8U, cv::Scalar(cv::GC_BGD));
  const cv::Rect inner = (box & frame) - roi.tl();
  cv::Mat bgd, fgd;
  cv::setRNGSeed(1);  // GrabCut's GMM initialisation draws random numbers: keep it reproducible
  cv::grabCut(crop, gc_mask, inner, bgd, fgd, 4, cv::GC_INIT_WITH_RECT);
  cv::Mat fg = (gc_mask == cv::GC_FGD) | (gc_mask == cv::GC_PR_FGD);
  // Keep the largest blob and smooth its outline.
  cv::morphologyEx(fg, fg, cv::MORPH_OPEN, cv::getStructuringElement(cv::MORPH_ELLIPSE, {5, 5}));
  cv::Mat labels, stats, centroids;
  const int n = cv::connectedComponentsWithStats(fg, labels, stats, centroids);
  int best = 0, best_area = 0;
  for (int i = 1; i < n; ++i) {
    if (stats.at<int>(i, cv::CC_STAT_AREA) > best_area) best_area = stats.at<int>(i, cv::CC_STAT_AREA), best = i;
  }
  cv::Mat out = cv::Mat::zeros(bgr.size(), CV_8U);
  if (best > 0) out(roi).setTo(255, labels == best);
  return out(box & frame).clone();
}

bool isWholeUprightPerson(const cv::Mat& mask) {
  if (mask.empty() || mask.cols > 0.45 * mask.rows) return false;
  cv::Mat rows;
  cv::reduce(mask, rows, 1, cv::REDUCE_MAX);  // one column: 255 on the rows the person is on
  const cv::Mat on = rows > 0;
  const int n = cv::countNonZero(on);
  if (n == 0) return false;
  int top = 0, bottom = mask.rows - 1;
  while (!on.at<uint8_t>(top)) ++top;
  while (!on.at<uint8_t>(bottom)) --bottom;
  return bottom - top + 1 >= 0.85 * mask.rows;
}

std::vector<PersonCutout> extractPersonCutouts(const std::string& folder, dynamic::YoloDetector& detector,
                                               int min_height, float min_score, bool whole_only) {
  namespace fs = std::filesystem;
  if (!fs::is_directory(folder)) throw InputError(fmt::format("people folder '{}' does not exist", folder));
  std::vector<fs::path> files;
  for (const auto& e : fs::directory_iterator(folder)) {
    const auto ext = e.path().extension().string();
    if (ext == ".png" || ext == ".jpg" || ext == ".jpeg") files.push_back(e.path());
  }
  std::sort(files.begin(), files.end());
  std::vector<PersonCutout> out;
  for (const auto& f : files) {
    const cv::Mat img = cv::imread(f.string(), cv::IMREAD_COLOR);
    if (img.empty()) continue;
    for (const auto& d : detector.detect(img)) {
      if (d.class_id != 0 || d.score < min_score || d.box.height < min_height) continue;
      const cv::Rect box = cv::Rect(d.box) & cv::Rect(0, 0, img.cols, img.rows);
      // Whole people only: a box touching the photo's border holds a cut-off body.
      if (box.x <= 2 || box.y <= 2 || box.br().x >= img.cols - 2 || box.br().y >= img.rows - 2) continue;
      PersonCutout c;
      c.mask = segmentInBox(img, box);
      // A good cut-out covers a fair part of its box; reject failed segmentations.
      const double fill = double(cv::countNonZero(c.mask)) / box.area();
      if (fill < 0.2 || fill > 0.9) continue;
      if (whole_only && !isWholeUprightPerson(c.mask)) continue;
      c.bgr = img(box).clone();
      c.source = f.filename().string();
      out.push_back(std::move(c));
    }
  }
  if (out.empty()) throw InputError(fmt::format("no usable person found in the photos of '{}'", folder));
  return out;
}

}  // namespace tkgslam::augment
