#pragma once
// Local mapping (ORB-SLAM2's LocalMapping for RGB-D): for each new keyframe it refreshes the
// covisibility graph, culls unreliable recent points, fuses duplicate points with neighbouring
// keyframes, runs a local bundle adjustment over the covisible window, and culls redundant
// keyframes. Takes the map lock only while it edits the map; the solver runs without it.
#include <list>
#include <memory>

#include "tkgslam/camera/PinholeCamera.h"
#include "tkgslam/data/Map.h"
#include "tkgslam/feature/ScalePyramid.h"
#include "tkgslam/match/OrbMatcher.h"
#include "tkgslam/optimize/LocalBundleAdjuster.h"
#include "tkgslam/system/SlamConfig.h"

namespace tkgslam::mapping {

struct MappingStats {
  int keyframes_processed = 0;
  int points_culled = 0;
  int points_fused = 0;
  int keyframes_culled = 0;
  double last_ba_ms = 0;
  int keyframes_held = 0;  ///< new keyframes a local BA moved too far, held at their tracked pose
};

class LocalMapper {
 public:
  LocalMapper(data::Map& map, const camera::PinholeCamera& camera, const feature::ScalePyramid& pyramid,
              const SlamConfig& config);

  /// Processes one keyframe produced by tracking. `more_pending` skips the bundle adjustment
  /// when further keyframes are already waiting (it will run for the next one).
  void process(const std::shared_ptr<data::KeyFrame>& kf, bool more_pending = false);

  const MappingStats& stats() const { return stats_; }

  /// Bundle adjustment over `kf` and its covisible keyframes (process() runs it); keyframes
  /// outside the window that see its points are held fixed, and so is keyframe 0.
  void localBundleAdjustment(data::KeyFrame& kf);

 private:
  void cullRecentPoints(data::KeyFrame& kf);
  void fuseWithNeighbours(data::KeyFrame& kf);
  /// Whether local BA moved a keyframe further than mapping.max_keyframe_shift_* (T_cw both).
  bool shiftedTooFar(const Pose& tracked, const Pose& solved) const;
  void cullKeyFrames(data::KeyFrame& kf);

  data::Map& map_;
  const camera::PinholeCamera& cam_;
  const feature::ScalePyramid& pyr_;
  const SlamConfig& cfg_;
  match::OrbMatcher matcher_;
  optimize::PinholeIntrinsics K_;
  std::list<std::shared_ptr<data::MapPoint>> recent_points_;
  MappingStats stats_;
};

}  // namespace tkgslam::mapping
