#pragma once
// Reading a colour (or grey) image the way every command expects it: 8-bit BGR.
#include <string>

#include <opencv2/core.hpp>

namespace tkgslam::io {

/// Reads `path` as 8-bit BGR (grey and BGRA converted). Throws InputError naming `what` and the path
/// when it cannot be read, is a JPEG cut short (it would decode with grey rows), is not 8-bit (a
/// 16-bit depth image given by mistake would otherwise be scaled down quietly) or has another
/// channel count.
cv::Mat readColourImage(const std::string& path, const std::string& what = "image");

/// An image's pixel format in words for error messages, e.g. "16-bit with 1 channel".
std::string describePixels(const cv::Mat& image);

}  // namespace tkgslam::io
