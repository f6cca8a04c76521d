#pragma once
// The map: keyframes and map points, and the one mutex that guards them and their links.
// Tracking holds the lock while it works on a frame (not during feature extraction); local
// mapping holds it while it edits the map (not while the bundle adjustment solver runs).
#include <algorithm>
#include <map>
#include <memory>
#include <mutex>
#include <vector>

#include "tkgslam/data/KeyFrame.h"
#include "tkgslam/data/MapPoint.h"

namespace tkgslam::data {

class Map {
 public:
  std::mutex& mutex() { return mutex_; }

  long newKeyFrameId() { return next_kf_id_++; }
  long newMapPointId() { return next_mp_id_++; }
  /// New ids continue after these (a map read back from a file keeps its ids).
  void continueIdsAfter(long keyframe_id, long map_point_id) {
    next_kf_id_ = std::max(next_kf_id_, keyframe_id + 1);
    next_mp_id_ = std::max(next_mp_id_, map_point_id + 1);
  }

  void addKeyFrame(const std::shared_ptr<KeyFrame>& kf);
  void addMapPoint(const std::shared_ptr<MapPoint>& mp);
  /// Marks the point bad and removes it from every keyframe that observes it.
  void eraseMapPoint(MapPoint* mp);
  /// Removes an observation; a point left with an observation weight <= 2 is erased.
  void eraseObservation(MapPoint* mp, KeyFrame* kf);
  /// Replaces `mp` by `by` everywhere (fusion of duplicates).
  void replaceMapPoint(MapPoint* mp, const std::shared_ptr<MapPoint>& by);
  /// Culls a keyframe: unlinks it from points, covisibility and the spanning tree.
  void eraseKeyFrame(KeyFrame* kf);

  std::shared_ptr<KeyFrame> keyFrame(long id) const;
  /// Active keyframes / points, ordered by id.
  std::vector<std::shared_ptr<KeyFrame>> keyFrames() const;
  std::vector<std::shared_ptr<MapPoint>> mapPoints() const;
  size_t keyFrameCount() const { return keyframes_.size(); }
  size_t mapPointCount() const { return points_.size(); }
  /// Every keyframe ever created (culled ones too), by id: frame poses are stored relative to one.
  const std::map<long, std::shared_ptr<KeyFrame>>& allKeyFrames() const { return all_keyframes_; }
  /// Drops every active keyframe and point (a new map segment starts); history is kept. The
  /// last `keep_features` keyframes (by id) keep their features, to re-anchor the next segment.
  void clearActive(size_t keep_features = 0);
  /// Moves the current map segment into another world frame: p_new = T_new_old * p_old for every
  /// active point, and the T_cw of every keyframe of the segment (culled ones too: frames may be
  /// stored relative to them) becomes T_cw * T_new_old^-1. Bumps generation().
  void transformActive(const Pose& T_new_old);
  /// Changes whenever the active map's world frame changes (transformActive, clearActive), so
  /// work computed outside the lock in the old frame (bundle adjustment) is not written back.
  long generation() const { return generation_; }
  /// The active keyframes and points were moved non-rigidly (loop closure): bumps generation().
  void noteCorrection() { ++generation_; }

 private:
  std::mutex mutex_;
  long next_kf_id_ = 0, next_mp_id_ = 0;
  long generation_ = 0;
  long segment_first_kf_id_ = 0;  ///< keyframes from this id on belong to the current segment
  std::map<long, std::shared_ptr<KeyFrame>> keyframes_;
  std::map<long, std::shared_ptr<MapPoint>> points_;
  std::map<long, std::shared_ptr<KeyFrame>> all_keyframes_;
};

}  // namespace tkgslam::data
