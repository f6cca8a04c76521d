#pragma once
// Loop closing for RGB-D (after ORB-SLAM2's LoopClosing, its vocabulary learnt from the map).
// A few wrong frames - people the detector missed, a blurred stretch - can put the camera, and
// every keyframe made after them, in a rotated and shifted copy of the world: the map forks, and
// tracking carries on consistently in the wrong frame because its local map holds only the new
// branch. When the camera then sees a place an older keyframe saw, this module finds the fork
// and closes it:
//  - detection: each new keyframe's static keypoints are matched by descriptors against the
//    points of the older keyframes it shares no map point with (the best-observed 300 of each) -
//    in a large map only against the loop.word_candidates of them most like it by visual words
//    (a vocabulary trained on the map's own descriptors once needed, again when the map doubled);
//    the best `loop.candidates` are verified: EPnP + RANSAC, the pose-only optimisation, then the
//    old keyframe's neighbourhood searched by projection and the pose optimised again (at least
//    loop.min_inliers inliers, depth included). A pose further than loop.min_correction_m / _deg
//    from the map's is a loop; with loop.confirm only once one of the next loop.confirm_within
//    keyframes finds the same correction (within 3 cm and 2 deg);
//  - correction: an SE(3) pose graph over the active keyframes - spanning tree and covisibility
//    edges weighted by their shared points, the loop edge far stronger - with the oldest keyframe
//    fixed, so the correction goes where the two branches are weakly tied (that may be the old
//    keyframe's side, when it is the one off); each point moves with its reference keyframe; the
//    old side's points are fused into the new keyframe and its neighbours, so local BA ties the
//    two branches together from then on;
//  - then, with loop.global_ba_iterations, a bundle adjustment over every active keyframe and
//    point refits what the rigid pose-graph moves left inconsistent (as ORB-SLAM2 does).
// Frame poses are stored relative to keyframes, so the trajectory follows the correction.
#include <cmath>
#include <memory>
#include <optional>
#include <vector>

#include "tkgslam/camera/PinholeCamera.h"
#include "tkgslam/data/Map.h"
#include "tkgslam/feature/ScalePyramid.h"
#include "tkgslam/match/OrbMatcher.h"
#include "tkgslam/optimize/PoseGraphOptimizer.h"
#include "tkgslam/optimize/PoseOptimizer.h"
#include "tkgslam/place/KeyFrameDatabase.h"
#include "tkgslam/system/SlamConfig.h"

namespace tkgslam::loop {

struct LoopStats {
  int keyframes_checked = 0;
  int candidates_considered = 0;  ///< old keyframes matched by descriptors (summed over keyframes)
  int candidates_matched = 0;  ///< keyframe pairs verified by PnP
  int vocabulary_trainings = 0;   ///< times the word index was (re)trained
  int consistent = 0;          ///< loops found where the map already has the camera
  int detected = 0;            ///< loops whose correction exceeded the thresholds
  int closed = 0;              ///< loops corrected
  double last_correction_m = 0;    ///< camera-centre shift of the last closing keyframe
  double last_correction_deg = 0;
  int global_bundles = 0;          ///< global bundle adjustments written back
  double last_global_ba_ms = 0;
  double total_ms = 0;             ///< time spent in process() (detection, correction, global BA)
};

class LoopCloser {
 public:
  LoopCloser(data::Map& map, const camera::PinholeCamera& camera, const feature::ScalePyramid& pyramid,
             const SlamConfig& config);

  /// Looks for a loop from `kf` (after local mapping has processed it) and closes it (a
  /// confirmed one with loop.confirm). Takes the map lock only while reading and while correcting. Returns true if the map
  /// was corrected.
  bool process(const std::shared_ptr<data::KeyFrame>& kf);

  const LoopStats& stats() const { return stats_; }

 private:
  struct Loop {
    std::shared_ptr<data::KeyFrame> kf;   ///< the new keyframe
    long old_id = -1;                     ///< the older keyframe it matched
    Pose T_cw_loop;       ///< kf's pose measured against old's points (old's world)
    Pose T_cw_map;        ///< kf's pose in the map when it was matched
    int inliers = 0;
    long generation = 0;  ///< map generation when matched
    /// T_loop_map = T_cw_loop^-1 * T_cw_map: moves the map's world into the loop-consistent one.
    Pose correction() const { return T_cw_loop.inverse() * T_cw_map; }
    /// How far the correction moves the new keyframe's camera centre (m), and turns it (deg).
    double shiftM() const {
      const Vec3 c = T_cw_map.inverse().translation();
      return (correction() * c - c).norm();
    }
    double angleDeg() const { return rotationAngle(correction().linear()) * 180.0 / M_PI; }
  };

  /// Keyframes at least loop.min_keyframe_gap older than `kf` that share no map point with it
  /// (map lock held).
  std::vector<std::shared_ptr<data::KeyFrame>> candidatesFor(const data::KeyFrame& kf) const;
  /// Of more than loop.word_candidates candidates, those most like the new keyframe's `query`
  /// features by words (the index brought up to date first, without the lock); all otherwise.
  std::vector<std::shared_ptr<data::KeyFrame>> mostSimilar(const data::FrameFeatures& query,
                                                           std::vector<std::shared_ptr<data::KeyFrame>> candidates);
  /// The points of `kf` and of its best covisible keyframes, each once (map lock held).
  static std::vector<std::shared_ptr<data::MapPoint>> pointsAround(const data::KeyFrame& kf);
  /// A copy of a map point's position, descriptor and viewing range (matching runs unlocked).
  static std::shared_ptr<data::MapPoint> copyOf(const data::MapPoint& mp);
  std::optional<Loop> detect(const std::shared_ptr<data::KeyFrame>& kf);
  /// A copy of old keyframe `c` holding copies of its best-observed points (kScoringPoints), so
  /// matching against it runs without the lock while mapping and tracking go on (map lock held).
  static std::unique_ptr<data::KeyFrame> scoringProbe(const data::KeyFrame& c);
  /// The new keyframe (`frame`, `base.kf`) against the probes: the loop.candidates with the most
  /// descriptor matches are verified, and of the loops whose correction exceeds the thresholds
  /// the one with the most inliers is returned. Lock not held while matching.
  std::optional<Loop> bestVerified(const data::Frame& frame, const std::vector<std::unique_ptr<data::KeyFrame>>& probes,
                                   const Loop& base);
  /// The new keyframe's pose from its descriptor matches to an old keyframe's points (RANSAC),
  /// refined with the old neighbourhood's points found by projection. Lock not held.
  std::optional<Loop> verify(const data::Frame& frame, const std::vector<std::shared_ptr<data::MapPoint>>& descriptor_matches,
                             const std::vector<std::shared_ptr<data::MapPoint>>& nearby, const Loop& base) const;
  /// Two detections agree on the correction (applied at the later keyframe's camera).
  static bool agree(const Loop& a, const Loop& b);
  bool close(const Loop& loop);
  /// The pose graph of the active keyframes `nodes` (in that order, the first fixed): spanning tree
  /// and covisibility edges weighted by shared points, plus the loop edge (map lock held). None if
  /// either end of the loop is not among `nodes`.
  static std::optional<optimize::PoseGraph> poseGraphFor(const std::vector<std::shared_ptr<data::KeyFrame>>& nodes,
                                                         const Loop& loop, const data::KeyFrame& old);
  /// Gives `nodes` their `corrected` poses (T_cw); each point moves with its reference keyframe,
  /// or the first observer among `nodes` (map lock held).
  void applyCorrection(const std::vector<std::shared_ptr<data::KeyFrame>>& nodes, const std::vector<Pose>& corrected);
  /// The two branches overlap after a correction: the old keyframe's neighbourhood's points are
  /// fused into `kf` and its best covisibles. Returns the points fused (map lock held).
  int fuseOldSide(data::KeyFrame& kf, const data::KeyFrame& old);
  /// Bundle adjustment over the active keyframes and points (the oldest fixed), after a closure.
  /// Solved without the lock; keyframes and points made meanwhile move with their parent /
  /// reference keyframe. Returns true if written back.
  bool globalBundleAdjustment();

  data::Map& map_;
  const camera::PinholeCamera& cam_;
  const feature::ScalePyramid& pyr_;
  const SlamConfig& cfg_;
  match::OrbMatcher matcher_;
  optimize::PinholeIntrinsics K_;
  std::optional<Loop> pending_;  ///< detected on a recent keyframe, awaiting confirmation
  int pending_waited_ = 0;       ///< keyframes checked since, without a detection
  place::KeyFrameDatabase places_{2.0};  ///< the map's keyframes by words, retrained when it doubled
  LoopStats stats_;
};

}  // namespace tkgslam::loop
