#pragma once
// A copy of fr1_xyz's first frames with faults written in (unreadable, black, mirrored, blurred or
// swapped images, truncated or missing depth, frames left out), for tests of bad input mid-run.
#include <cmath>
#include <filesystem>
#include <functional>
#include <string>

#include <fmt/format.h>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "TestSupport.h"
#include "tkgslam/io/TumDataset.h"

namespace tkgslam::test {

/// What to write for one frame of a copied fr1_xyz sequence: the original file, or a stand-in.
enum class FrameFault { None, Unreadable, Black, TruncatedDepth, NoDepth, Mirrored, MotionBlur, Swapped };
/// FrameFault::Swapped: the frame's images are those of the frame this many frames later.
constexpr int kSwapOffset = 30;

inline cv::Mat mirrored(const std::string& path, int flags) {
  cv::Mat m;
  cv::flip(cv::imread(path, flags), m, 1);
  return m;
}

/// Camera shake during the exposure: a 31 px straight smear at `angle` radians.
inline cv::Mat motionBlurred(const std::string& path, double angle) {
  cv::Mat kernel = cv::Mat::zeros(31, 31, CV_32F);
  const cv::Point2d d(15 * std::cos(angle), 15 * std::sin(angle));
  cv::line(kernel, cv::Point2d(15, 15) - d, cv::Point2d(15, 15) + d, cv::Scalar(1.0));
  kernel /= cv::sum(kernel)[0];
  cv::Mat m;
  cv::filter2D(cv::imread(path, cv::IMREAD_COLOR), m, -1, kernel);
  return m;
}

/// Writes the first `frames` frames of fr1_xyz to `seq` (TUM layout, with ground truth), leaving out
/// those `skip` returns true for and replacing images as `rgb_fault` / `depth_fault` say.
inline void writeFaultySequence(const std::filesystem::path& seq, int frames, const std::function<bool(int)>& skip,
                         const std::function<FrameFault(int)>& rgb_fault,
                         const std::function<FrameFault(int)>& depth_fault) {
  std::filesystem::create_directories(seq / "rgb");
  std::filesystem::create_directories(seq / "depth");
  io::TumDataset src(fr1xyz().string());
  std::string rgb_list, depth_list;
  for (int i = 0; i < frames; ++i) {
    if (skip(i)) continue;
    const auto& e = src.entry(i);
    const std::filesystem::path rgb = seq / "rgb" / std::filesystem::path(e.rgb_path).filename();
    const std::filesystem::path depth = seq / "depth" / std::filesystem::path(e.depth_path).filename();
    switch (rgb_fault(i)) {
      case FrameFault::Unreadable: writeText(rgb, "not an image"); break;
      case FrameFault::Black: cv::imwrite(rgb.string(), cv::Mat::zeros(480, 640, CV_8UC3)); break;
      case FrameFault::Mirrored: cv::imwrite(rgb.string(), mirrored(e.rgb_path, cv::IMREAD_COLOR)); break;
      case FrameFault::MotionBlur: cv::imwrite(rgb.string(), motionBlurred(e.rgb_path, 0.3 * i)); break;
      case FrameFault::Swapped: std::filesystem::copy_file(src.entry(i + kSwapOffset).rgb_path, rgb); break;
      default: std::filesystem::copy_file(e.rgb_path, rgb);
    }
    switch (depth_fault(i)) {
      case FrameFault::TruncatedDepth: writeText(depth, readFile(e.depth_path).substr(0, 200)); break;
      case FrameFault::NoDepth: cv::imwrite(depth.string(), cv::Mat::zeros(480, 640, CV_16UC1)); break;
      case FrameFault::Mirrored: cv::imwrite(depth.string(), mirrored(e.depth_path, cv::IMREAD_ANYDEPTH)); break;
      case FrameFault::Swapped: std::filesystem::copy_file(src.entry(i + kSwapOffset).depth_path, depth); break;
      default: std::filesystem::copy_file(e.depth_path, depth);
    }
    rgb_list += fmt::format("{:.6f} rgb/{}\n", e.rgb_timestamp, rgb.filename().string());
    depth_list += fmt::format("{:.6f} depth/{}\n", e.depth_timestamp, depth.filename().string());
  }
  writeText(seq / "rgb.txt", rgb_list);
  writeText(seq / "depth.txt", depth_list);
  std::filesystem::copy_file(fr1xyz() / "groundtruth.txt", seq / "groundtruth.txt");
}

}  // namespace tkgslam::test
