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
    throw InputError(fmt::format("{} '{}' is not an 8-bit image (a depth image?)", what, path));
  }
  switch (image.channels()) {
    case 1: cv::cvtColor(image, image, cv::COLOR_GRAY2BGR); break;
    case 3: break;
    case 4: cv::cvtColor(image, image, cv::COLOR_BGRA2BGR); break;
    default: throw InputError(fmt::format("{} '{}' has {} channels", what, path, image.channels()));
  }
  return image;
}

}  // namespace tkgslam::io
