#pragma once
// Aggregated configuration of the whole system, one struct per module.
#include <cstdint>
#include <string>

#include "tkgslam/camera/PinholeCamera.h"
#include "tkgslam/feature/OrbExtractor.h"

namespace tkgslam {

/// RGB-D specifics. Depth images are registered to the colour image.
struct DepthParams {
  double factor = 5000.0;          ///< raw depth units per metre
  double baseline_fx = 40.0;       ///< virtual stereo baseline times fx (m*px): u_right = u - bf/z
  double close_threshold = 3.09;   ///< m; depth below this is trusted for new map points
  double max_depth = 8.0;          ///< m; depth beyond this is ignored
};

struct TrackingParams {
  int min_init_features = 500;     ///< keypoints with depth needed to start a map
  int min_tracked_inliers = 30;    ///< below this after local-map tracking, the frame is lost
  int max_frames_between_keyframes = 30;  ///< 0 = camera fps
  int relocalization_attempts = 5; ///< lost frames before a new map segment is started
};

struct MappingParams {
  int local_ba_iterations = 10;
  int covisible_keyframes = 10;    ///< neighbours used for fusion
  double keyframe_redundancy = 0.9;  ///< cull a keyframe when this share of its points is seen elsewhere
  bool cull_keyframes = true;
};

struct SlamConfig {
  std::string source;  ///< file the config came from
  camera::CameraParams camera;
  DepthParams depth;
  feature::OrbParams orb;
  TrackingParams tracking;
  MappingParams mapping;
  bool deterministic = false;
  std::uint64_t seed = 42;
};

}  // namespace tkgslam
