#pragma once
// A tiny valid TUM-layout sequence for io tests: JPEG colour (frame i is the flat colour
// (10, 20, 30 + i)), 16-bit depth of 1 m, timestamps 100, 101, ... (depth 0.01 s later).
#include <filesystem>
#include <string>

#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>

#include "TestSupport.h"

namespace tkgslam::test {

inline void writeTinyTumSequence(const std::filesystem::path& dir, int frames = 3, int w = 64, int h = 48) {
  std::filesystem::create_directories(dir / "rgb");
  std::filesystem::create_directories(dir / "depth");
  std::string rgb = "# color images\n# timestamp filename\n", depth = "# depth\n";
  for (int i = 0; i < frames; ++i) {
    const std::string t = std::to_string(100 + i) + ".000000";
    const std::string td = std::to_string(100 + i) + ".010000";
    cv::imwrite((dir / "rgb" / (t + ".jpg")).string(), cv::Mat(h, w, CV_8UC3, cv::Scalar(10, 20, 30 + i)));
    cv::imwrite((dir / "depth" / (td + ".png")).string(), cv::Mat(h, w, CV_16UC1, cv::Scalar(5000)));
    rgb += t + " rgb/" + t + ".jpg\n";
    depth += td + " depth/" + td + ".png\n";
  }
  writeText(dir / "rgb.txt", rgb);
  writeText(dir / "depth.txt", depth);
}

}  // namespace tkgslam::test
