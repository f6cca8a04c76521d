#pragma once
// The tracker's record of one posed frame: its pose relative to its reference keyframe, so that
// later keyframe corrections (bundle adjustment, loop closing) also move it.
#include <memory>
#include <vector>

#include "tkgslam/common/Pose.h"
#include "tkgslam/data/KeyFrame.h"
#include "tkgslam/data/MapPoint.h"

namespace tkgslam::tracking {

/// One inlier match of a tracked frame, kept until its pose is checked against the map
/// (Tracker::checkPosesAgainstMap).
struct RecordedMatch {
  std::weak_ptr<data::MapPoint> point;  ///< not kept alive: a point culled since no longer counts
  float u = 0, v = 0;                   ///< ideal pixel
  float u_right = -1;                   ///< virtual right-camera u, < 0 = none
  int octave = 0;
};

/// A frame's pose stored relative to its reference keyframe.
struct FrameRecord {
  FrameRecord() = default;
  FrameRecord(double t, std::shared_ptr<data::KeyFrame> ref, const Pose& T, bool is_provisional = false)
      : timestamp(t), reference(std::move(ref)), T_cr(T), provisional(is_provisional) {}

  double timestamp = 0;  ///< seconds
  std::shared_ptr<data::KeyFrame> reference;
  Pose T_cr = Pose::Identity();  ///< reference keyframe -> camera
  /// The pose is provisional: the motion model's prediction (a bridged frame), or tracked on a
  /// motion-blurred image (smeared keypoints). Once tracking resumes on a later frame it is
  /// replaced by the pose interpolated between the frames tracked either side.
  bool provisional = false;
  /// The pose is the motion model's prediction (a bridged frame), not tracked.
  bool predicted = false;
  /// The pose was interpolated between the tracked records either side (the ones next to this
  /// frame's run of interpolated records); interpolateAgain redoes it at the end.
  bool interpolated = false;
  /// A tracked frame's inlier matches, until its pose has been checked (TrackingParams::pose_check_m).
  std::vector<RecordedMatch> matches;

  /// World -> camera pose through the reference keyframe as it is now; a culled reference is
  /// replaced by its spanning-tree parent.
  Pose T_cw() const;
  /// Sets T_cr so that T_cw() is `T_cw` with the reference keyframes as they are now.
  void setT_cw(const Pose& T_cw);
};

}  // namespace tkgslam::tracking
