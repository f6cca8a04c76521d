#include "tkgslam/io/ColourImage.h"

#include <fmt/format.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "tkgslam/common/Error.h"

namespace tkgslam::io {

cv::Mat readColourImage(const std::string& path, const std::string& what) {
  cv::Mat image = cv::imread(path, cv::IMREAD_UNCHANGED);
  if (image.empty()) throw InputError(fmt::format("cannot read {} '{}'", what, path));
  if (image.depth() != CV_8U) {
    throw InputError(
        fmt::format("{} '{}' is not an 8-bit image (a depth image?): it is {}", what, path, describePixels(image)));
  }
  switch (image.channels()) {
    case 1: cv::cvtColor(image, image, cv::COLOR_GRAY2BGR); break;
    case 3: break;
    case 4: cv::cvtColor(image, image, cv::COLOR_BGRA2BGR); break;
    default: throw InputError(fmt::format("{} '{}' has {} channels", what, path, image.channels()));
  }
  return image;
}

std::string describePixels(const cv::Mat& image) {
  static const char* const kDepths[] = {"8-bit",        "8-bit signed", "16-bit",       "16-bit signed",
                                        "32-bit integer", "32-bit float", "64-bit float", "16-bit float"};
  const int depth = image.depth();
  const char* name = depth >= 0 && depth < 8 ? kDepths[depth] : "unknown";
  return fmt::format("{} with {} channel{}", name, image.channels(), image.channels() == 1 ? "" : "s");
}

}  // namespace tkgslam::io
