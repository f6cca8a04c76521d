#include "tkgslam/system/FrameInput.h"

#include <cmath>
#include <cstdint>

#include <fmt/format.h>
#include <opencv2/imgproc.hpp>

#include "tkgslam/common/Error.h"
#include "tkgslam/io/ColourImage.h"

namespace tkgslam {
namespace {

/// Throws unless `image` is of `type` and `size`; `what` names it and the format it should have.
void requireImage(const cv::Mat& image, int type, cv::Size size, const char* what, const char* expected,
                  const char* hint = "") {
  if (image.empty()) throw InputError(fmt::format("processFrame: {} is empty (expected {})", what, expected));
  if (image.type() != type) {
    throw InputError(
        fmt::format("processFrame: {} must be {}; it is {}{}", what, expected, io::describePixels(image), hint));
  }
  if (image.size() != size) {
    throw InputError(fmt::format("processFrame: {} is {}x{} but the camera config says {}x{}", what, image.cols,
                                 image.rows, size.width, size.height));
  }
}

/// Whether every value of a CV_32F image is finite. (cv::checkRange took 150-250 us a VGA frame,
/// 1-2 % of ORB + tracking; this loop vectorises: an exponent of all ones is NaN or infinite.)
bool allFinite(const cv::Mat& image) {
  for (int r = 0; r < image.rows; ++r) {
    const auto* bits = image.ptr<uint32_t>(r);
    uint32_t bad = 0;
    for (int c = 0; c < image.cols; ++c) bad |= uint32_t((bits[c] & 0x7f800000u) == 0x7f800000u);
    if (bad) return false;
  }
  return true;
}

}  // namespace

io::RgbdImages checkFrameImages(io::RgbdImages images, cv::Size camera_size,
                                std::optional<double> previous_timestamp) {
  if (!std::isfinite(images.timestamp)) throw InputError("processFrame: the timestamp is not a finite number");
  if (previous_timestamp && !(images.timestamp > *previous_timestamp)) {
    throw InputError(fmt::format("processFrame: timestamp {:.6f} is not after the previous frame's ({:.6f})",
                                 images.timestamp, *previous_timestamp));
  }
  requireImage(images.bgr, CV_8UC3, camera_size, "bgr", "8-bit with 3 channels (BGR)");
  requireImage(images.depth_m, CV_32FC1, camera_size, "depth_m", "32-bit float metres with 1 channel",
               images.depth_m.depth() == CV_16U ? " (raw depth: convertTo(depth_m, CV_32F, 1.0 / depth_factor))" : "");
  if (!allFinite(images.depth_m)) {
    // NaN or infinite depths (some drivers' "no depth") become 0, in a copy: the caller's buffer stays.
    cv::Mat depth = images.depth_m.clone();
    depth.forEach<float>([](float& d, const int*) {
      if (!std::isfinite(d)) d = 0.0f;
    });
    images.depth_m = depth;
  }
  if (images.gray.empty()) {
    cv::cvtColor(images.bgr, images.gray, cv::COLOR_BGR2GRAY);
  } else {
    requireImage(images.gray, CV_8UC1, camera_size, "gray", "8-bit with 1 channel (or empty)");
  }
  if (!images.truth_mask.empty()) {
    requireImage(images.truth_mask, CV_8UC1, camera_size, "truth_mask", "8-bit with 1 channel (or empty)");
  }
  return images;
}

}  // namespace tkgslam
