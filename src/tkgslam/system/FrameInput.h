#pragma once
// The frame an application hands to SlamSystem::processFrame, checked. TumDataset::load checks the
// files it reads; a frame built in memory (a live camera) got no check, and a raw 16-bit depth
// image passed as depth_m was read as floats: out of bounds, or depths of thousands of metres.
#include <optional>

#include <opencv2/core.hpp>

#include "tkgslam/io/TumDataset.h"

namespace tkgslam {

/// Checks `images` against the camera's image size and the frame before, and fills in what may be
/// left out: `gray` (made from `bgr` when empty). Expected: `bgr` 8-bit 3-channel BGR of
/// `camera_size`; `depth_m` 32-bit float metres, 1 channel, the same size (0 = no depth; NaN and
/// infinite values are set to 0 in a copy);
/// `truth_mask` empty or 8-bit 1-channel; `timestamp` finite seconds, after `previous_timestamp`.
/// Throws InputError saying which image is wrong and how.
io::RgbdImages checkFrameImages(io::RgbdImages images, cv::Size camera_size,
                                std::optional<double> previous_timestamp);

}  // namespace tkgslam
