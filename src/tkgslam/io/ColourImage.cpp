#include "tkgslam/io/ColourImage.h"

#include <fstream>
#include <iterator>
#include <vector>

#include <fmt/format.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "tkgslam/common/Error.h"

namespace tkgslam::io {

namespace {

/// A JPEG cut short (a copy or download that stopped) still decodes: libjpeg fills the missing rows
/// with grey and only warns on stderr, and SLAM would track a half-grey frame. Such a file lacks the
/// end-of-image marker FF D9, which entropy-coded data cannot contain (an FF there is followed by 00
/// or a restart code). Some writers pad after the marker, so it is looked for in the last KiB.
bool isTruncatedJpeg(const std::vector<uchar>& bytes) {
  if (bytes.size() < 4 || bytes[0] != 0xFF || bytes[1] != 0xD8) return false;
  const std::size_t first = bytes.size() > 1024 ? bytes.size() - 1024 : 2;
  for (std::size_t i = bytes.size() - 1; i > first; --i) {
    if (bytes[i - 1] == 0xFF && bytes[i] == 0xD9) return false;
  }
  return true;
}

}  // namespace

cv::Mat readColourImage(const std::string& path, const std::string& what) {
  std::ifstream in(path, std::ios::binary);
  const std::vector<uchar> bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (!in || bytes.empty()) throw InputError(fmt::format("cannot read {} '{}'", what, path));
  if (isTruncatedJpeg(bytes)) {
    throw InputError(fmt::format("{} '{}' is a truncated JPEG (its end-of-image marker is missing)", what, path));
  }
  cv::Mat image = cv::imdecode(bytes, cv::IMREAD_UNCHANGED);
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
