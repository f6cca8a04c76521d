#pragma once
// How depth images are read and weighted.

namespace tkgslam {

/// RGB-D specifics. Depth images are registered to the colour image.
struct DepthParams {
  double factor = 5000.0;          ///< raw depth units per metre
  double baseline_fx = 40.0;       ///< virtual stereo baseline times fx (m*px): u_right = u - bf/z
  double close_threshold = 3.09;   ///< m; depth below this is trusted for new map points
  double max_depth = 8.0;          ///< m; depth beyond this is ignored
};

}  // namespace tkgslam
