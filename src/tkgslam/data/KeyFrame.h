#pragma once
// A keyframe: a frame kept in the map, with its features, pose, map-point associations and
// covisibility links. All members are read and written with the Map's mutex held.
#include <map>
#include <memory>
#include <set>
#include <vector>

#include "tkgslam/common/Pose.h"
#include "tkgslam/data/FrameFeatures.h"
#include "tkgslam/data/MapPoint.h"

namespace tkgslam::data {

class KeyFrame {
 public:
  KeyFrame(long id, long frame_id, double timestamp, std::shared_ptr<const FrameFeatures> features,
           const Pose& T_cw);

  const long id;
  const long frame_id;
  const double timestamp;
  std::shared_ptr<const FrameFeatures> features;
  std::vector<std::shared_ptr<MapPoint>> map_points;  ///< per keypoint, may be null

  const Pose& T_cw() const { return T_cw_; }
  const Pose& T_wc() const { return T_wc_; }
  Vec3 centre() const { return T_wc_.translation(); }
  void setPose(const Pose& T_cw) {
    T_cw_ = T_cw;
    T_wc_ = T_cw.inverse();
  }

  // Covisibility graph: weight = number of shared map points.
  std::map<KeyFrame*, int, KeyFrameIdLess> connections;
  std::vector<KeyFrame*> ordered_connections;  ///< by weight descending, then id
  /// Rebuilds this keyframe's links from its map points' observations (links both ways).
  void updateConnections();
  void eraseConnection(KeyFrame* kf);
  std::vector<KeyFrame*> bestCovisibles(int n) const;

  // Spanning tree (for the trajectory of frames whose reference keyframe was culled).
  KeyFrame* parent = nullptr;
  std::set<KeyFrame*, KeyFrameIdLess> children;
  Pose T_c_parent = Pose::Identity();  ///< fixed when this keyframe is culled

  bool bad = false;
  bool not_erase = false;  ///< protected from culling (e.g. the first keyframe)

  /// Map points seen by at least `min_obs` keyframes.
  int trackedMapPoints(int min_obs) const;
  void addMapPoint(const std::shared_ptr<MapPoint>& mp, int idx) { map_points[idx] = mp; }
  /// Frees the keypoints, descriptors and point links of a keyframe that left the active map
  /// (culled, or in a finished map segment). Only its pose and spanning-tree links stay: frame
  /// poses are stored relative to it. Keeps memory flat on long runs.
  void releaseFeatures() {
    features.reset();
    std::vector<std::shared_ptr<MapPoint>>().swap(map_points);
  }
  void eraseMapPoint(int idx) { map_points[idx].reset(); }

  // Scratch for local mapping / tracking.
  long fuse_target_for = -1;
  long track_reference_for = -1;

 private:
  void sortConnections();
  Pose T_cw_, T_wc_;
};

}  // namespace tkgslam::data
