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
/// with grey and only warns on stderr, and SLAM would track a half-grey frame. Such a file has no
/// end-of-image marker (FF D9) after its first scan. The header segments before that scan are
/// stepped over by their lengths (an EXIF thumbnail there has a marker of its own); the scan data
/// cannot hold the pair (an FF in it is followed by 00 or a restart code). Data some cameras append
/// after the marker does not matter. What is not laid out like that is left to the decoder.
bool isTruncatedJpeg(const std::vector<uchar>& bytes) {
  const std::size_t n = bytes.size();
  if (n < 4 || bytes[0] != 0xFF || bytes[1] != 0xD8) return false;
  std::size_t i = 2;
  for (;;) {
    if (i + 4 > n) return false;  // cut within the headers: the decoder refuses it
    if (bytes[i] != 0xFF) return false;
    const uchar marker = bytes[i + 1];
    if (marker == 0xFF) {  // fill byte
      ++i;
      continue;
    }
    if (marker == 0xD9) return false;
    i += 2 + ((std::size_t(bytes[i + 2]) << 8) | bytes[i + 3]);
    if (marker == 0xDA) break;  // start of the first scan
  }
  // From the end back: a whole file has the marker at its end or before a short trailer, so a
  // frame's check reads a few bytes, not its whole scan.
  for (std::size_t j = n - 1; j > i; --j) {
    if (bytes[j - 1] == 0xFF && bytes[j] == 0xD9) return false;
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
  // Any depth (a 16-bit image is refused below, not scaled down) and colour, turned as an EXIF
  // orientation tag says (phone photos are stored sideways); IMREAD_UNCHANGED would not turn them.
  cv::Mat image = cv::imdecode(bytes, cv::IMREAD_ANYDEPTH | cv::IMREAD_ANYCOLOR);
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
