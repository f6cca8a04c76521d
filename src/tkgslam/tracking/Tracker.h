#pragma once
// Camera tracking (ORB-SLAM2's RGB-D tracking): map initialisation from the first frame with
// enough depth, constant-velocity motion model with projection matching, fallback to the
// reference keyframe, local-map tracking, keyframe decision, relocalisation when lost and a new
// map segment when relocalisation keeps failing. Beyond ORB-SLAM2: a few untrackable frames are
// bridged by the motion model, and a new segment is re-anchored (one rigid correction) to the
// previous one once it sees the same scene again. Never aborts the run.
#include <functional>
#include <deque>
#include <memory>
#include <optional>
#include <vector>

#include "tkgslam/camera/PinholeCamera.h"
#include "tkgslam/data/Frame.h"
#include "tkgslam/data/Map.h"
#include "tkgslam/feature/ScalePyramid.h"
#include "tkgslam/match/OrbMatcher.h"
#include "tkgslam/optimize/PoseOptimizer.h"
#include "tkgslam/place/KeyFrameDatabase.h"
#include "tkgslam/system/SlamConfig.h"
#include "tkgslam/tracking/FrameRecord.h"

namespace tkgslam::tracking {

enum class TrackingState { NotInitialized, Ok, Lost };

/// What the caller needs to know about one tracked frame.
struct TrackResult {
  bool tracked = false;
  std::shared_ptr<data::KeyFrame> new_keyframe;  ///< to hand to local mapping
  int inliers = 0;
  bool new_segment = false;  ///< a new map segment was started at this frame
  /// Too few matches to track, but the motion model bridged the frame: the pose is the constant-
  /// velocity prediction (tracked is also true). See TrackingParams::max_predicted_frames.
  bool predicted = false;
  /// The current map segment was moved into the previous segment's frame at this frame.
  bool reanchored = false;
  /// The image is much less sharp than the frames before it (TrackingParams::blur_ratio).
  bool blurred = false;
  /// Dynamic-object boxes cover most of the image (TrackingParams::covered_ratio).
  bool covered = false;
  /// The tracked pose jumped away from the motion model's prediction (TrackingParams::max_jump_deg)
  /// and was not used; the frame was then bridged or lost like an untrackable one.
  bool jump_rejected = false;
  /// Relocalised soon after a loss, or re-anchored a new segment that started right after one:
  /// the timestamps of the frames lost in between, which now have poses interpolated between the
  /// frames tracked either side (see Tracker::track).
  std::vector<double> interpolated_lost;
  /// Camera-to-world pose of this frame (metres) as tracking has it now, set when `tracked`: what a
  /// live application uses. Later frames refine the map, so trajectory() may differ by millimetres
  /// (local BA), more after a loop closure, and replaces provisional (predicted, blurred) poses.
  std::optional<Pose> T_wc;
};

/// Called once the frame has a pose from the keypoints outside the boxes; may re-admit or exclude
/// keypoints (frame.features->excluded). Receives the local keyframes; returns how many changed.
using RefineKeypoints =
    std::function<int(data::Frame& frame, const std::vector<std::shared_ptr<data::KeyFrame>>& local_keyframes)>;

class Tracker {
 public:
  Tracker(data::Map& map, const camera::PinholeCamera& camera, const feature::ScalePyramid& pyramid,
          const SlamConfig& config);

  /// Tracks one frame. `mapper_idle` / `mapper_queue` describe local mapping's state (keyframe
  /// decision). Takes the map lock for the duration of the call.
  TrackResult track(data::Frame frame, bool mapper_idle, int mapper_queue, const RefineKeypoints& refine = {});

  TrackingState state() const { return state_; }
  /// The map holds a map read from a file (io::readMapFile) and nothing else yet: tracking starts
  /// lost, relocalising against all of that map's keyframes (not only the recent ones) until it
  /// finds the camera, so this run's poses come out in that map's world frame. If it keeps
  /// failing, a new map segment starts as after any loss (at the identity: no pose is known),
  /// re-anchored to the loaded map's last keyframes once it sees what they saw. Call before the
  /// first frame. `localization_only`: the map is only tracked against, never changed - no
  /// keyframes, no map points, no new segment when lost; lost frames keep relocalising in the
  /// whole map until the camera is found again. The loaded keyframes are indexed by their words
  /// (place::KeyFrameDatabase, a vocabulary trained on their own descriptors), so a lost frame tries
  /// only the most similar ones (`tracking.relocalization_candidates`). Map lock held.
  void startInLoadedMap(bool localization_only = false);
  /// An image of this sharpness (feature::imageSharpness) would count as motion-blurred now
  /// (TrackingParams::blur_ratio of the recent sharp frames' median). Call from the tracking thread.
  bool looksBlurred(double sharpness) const;
  /// Tracked (and motion-model predicted) frames so far; lost frames have no record.
  const std::vector<FrameRecord>& records() const { return records_; }
  /// Checks the tracked frames not checked yet against the map as it is now (TrackingParams::
  /// pose_check_m): a frame whose own matches put it further than that from its stored pose gets
  /// that pose. Call at the end of a run (frames older than kPoseCheckWindow are checked as tracking
  /// goes on, so that their matches need not be kept). Returns the poses replaced. Takes the map lock.
  int checkPosesAgainstMap();
  /// End-of-run repairs of the records (TrajectoryRepair.h), called in this order after
  /// checkPosesAgainstMap; each takes the map lock and returns the records posed again.
  /// Interpolated records again, between the final poses of the records either side.
  int interpolateAgainInFinalMap();
  /// Frames bridged after the last tracked one, moved on by the median of kEndSteps steps.
  int extrapolateEndAgainInFinalMap();
  /// Excursions of up to kExcursionFrames records (TrackingParams::excursion_m).
  int interpolateExcursions();
  /// The most recent frame (features, matches, pose) - for diagnostics.
  const data::Frame* lastFrame() const { return last_frame_.get(); }

 private:
  static constexpr size_t kAnchorCandidates = 20;  ///< previous segment's keyframes kept
  static constexpr size_t kAnchorTries = 3;        ///< of them tried per new keyframe
  static constexpr int kAnchorAttempts = 40;       ///< new keyframes that try before giving up
  /// A wrong correction would move the whole segment: as many inliers (reprojection and depth
  /// both consistent) as ORB-SLAM2 asks of a loop closure, more than of a relocalisation.
  static constexpr int kAnchorMinInliers = 40;
  /// Records whose matches are kept for the pose check (30 s at 30 Hz; ~8 kB each).
  static constexpr size_t kPoseCheckWindow = 900;
  static constexpr size_t kEndSteps = 5;  ///< steps whose median moves the records at the end
  static constexpr size_t kExcursionFrames = 3;  ///< longest run of records interpolateExcursions replaces
  static constexpr size_t kSharpnessWindow = 15;  ///< sharp frames whose median sharpness is the yardstick

  /// track() under the map lock.
  TrackResult trackLocked(data::Frame frame, bool mapper_idle, int mapper_queue, const RefineKeypoints& refine);
  /// Tracks the frame against the last frame or the reference keyframe, or relocalises it when
  /// lost, then against the local map; `refine` (the geometry check) runs on the pose found, or on
  /// the motion model's prediction when the keypoints outside the boxes were too few. Sets
  /// `*rescued` when only keypoints the check re-admitted tracked the frame. True if tracked.
  bool estimatePose(data::Frame& frame, const RefineKeypoints& refine, bool* rescued);
  /// The tracked pose is further from the motion model's prediction than the camera can move
  /// (poseJumped), where there is a prediction to compare with.
  bool jumpedFromMotionModel(const data::Frame& frame) const;
  /// A tracked frame: records it (provisionally if blurred), updates the velocity, makes a keyframe
  /// if one is needed, and interpolates the frames bridged or lost before it. Becomes the last frame.
  void keepTrackedFrame(data::Frame&& frame, bool after_loss, bool rescued, bool mapper_idle, int mapper_queue,
                        TrackResult& result);
  /// An untracked frame in a tracked run gets the motion model's pose, if not too many in a row
  /// have. False if the frame is not bridged.
  bool bridgeFrame(data::Frame& frame, TrackResult& result);
  /// An untracked frame that is not bridged: tracking is lost; a new map segment starts on it when
  /// relocalisation has kept failing.
  void loseFrame(data::Frame& frame, TrackResult& result);
  /// Blurred and covered frames are bridged for longer than sharp ones: they are expected to fail.
  int maxGapFrames() const { return 3 * cfg_.tracking.max_predicted_frames; }
  bool canInitialize(const data::Frame& frame) const;
  bool initialize(data::Frame& frame, bool new_segment);
  bool trackWithMotionModel(data::Frame& frame);
  bool trackReferenceKeyFrame(data::Frame& frame);
  bool relocalize(data::Frame& frame);
  /// The keyframes a lost frame tries, in order: a loaded map's most similar ones (index), then
  /// the recent ones the index does not hold (all of them while searching the whole map).
  std::vector<std::shared_ptr<data::KeyFrame>> relocalizationCandidates(const data::Frame& frame) const;
  /// Relocalisation goes back to the recent keyframes (found in the loaded map, or a new segment).
  void searchRecentKeyFramesOnly();
  /// A new map segment started at the last known pose, off by however far the camera moved while
  /// lost. Once a new keyframe sees what one of the previous segment's last keyframes saw, the
  /// segment is moved into the previous segment's world frame (one rigid correction), so both
  /// halves of the trajectory line up. Returns true when it did; the frames lost just before the
  /// segment started that then got poses are appended to `interpolated_lost`.
  bool reanchorSegment(data::Frame& frame, std::vector<double>& interpolated_lost);
  void releaseAnchor();
  /// After a re-anchoring to the segment before: the frames lost just before this segment started
  /// get poses interpolated as after a quick relocalisation; their timestamps are appended to
  /// `interpolated_lost`.
  void poseFramesLostBeforeSegment(const data::KeyFrame& anchor, std::vector<double>& interpolated_lost);
  bool trackLocalMap(data::Frame& frame);
  void updateLastFrame();
  void updateLocalMap(data::Frame& frame);
  int searchLocalPoints(data::Frame& frame);
  bool needNewKeyFrame(const data::Frame& frame, bool mapper_idle, int mapper_queue) const;
  std::shared_ptr<data::KeyFrame> createKeyFrame(data::Frame& frame);
  /// Drops outlier matches; returns the matches that are map points (not temporary ones).
  int discardOutliers(data::Frame& frame);
  /// Records the frame's sharpness; true if it is blurred relative to the recent frames.
  bool checkBlurred(const data::Frame& frame);
  /// Constant-velocity prediction for the current frame: `gap_frames_ + 1` steps of the last
  /// velocity from the last frame tracked against.
  Pose predictPose() const;
  /// Tracking resumed (or relocalised) after frames posed without a new last frame: their
  /// provisional records get the pose interpolated (by timestamp) between the last frame and this one,
  /// and so do the `lost` frames (timestamps, after the bridged ones), which get records first.
  /// False if there was nothing to interpolate from (the records are left as they are).
  bool interpolateBridgedRecords(const std::vector<double>& lost);
  /// The tracked pose is further from the constant-velocity prediction than a camera moves in
  /// `periods` frame periods (the tracking.max_jump_* limits are per period).
  bool poseJumped(const Pose& T_cw, int periods) const;
  /// The pose check of one record (see checkPosesAgainstMap); releases its matches. True if the
  /// pose was replaced.
  bool checkRecordPose(FrameRecord& record);

  data::Map& map_;
  const camera::PinholeCamera& cam_;
  const feature::ScalePyramid& pyr_;
  const SlamConfig& cfg_;
  match::OrbMatcher matcher_;
  optimize::PinholeIntrinsics K_;

  TrackingState state_ = TrackingState::NotInitialized;
  std::unique_ptr<data::Frame> last_frame_;
  std::shared_ptr<data::KeyFrame> reference_kf_;
  std::shared_ptr<data::KeyFrame> last_kf_;
  std::vector<std::shared_ptr<data::KeyFrame>> local_keyframes_;
  std::vector<std::shared_ptr<data::MapPoint>> local_points_;
  std::vector<std::shared_ptr<data::MapPoint>> temporal_points_;  ///< visual-odometry points
  Pose velocity_ = Pose::Identity();  ///< T_cur,last of the last tracked step
  bool has_velocity_ = false;
  long last_reloc_frame_ = -1000;
  bool relocalize_in_whole_map_ = false;  ///< see startInLoadedMap()
  bool localization_only_ = false;        ///< see startInLoadedMap()
  place::KeyFrameDatabase loaded_places_;  ///< a loaded map's keyframes by words
  int lost_frames_ = 0;
  /// Timestamps of the frames lost since the last tracked one, while relocalisation may still
  /// find the camera soon enough for them to be interpolated (at most relocalization_attempts).
  std::vector<double> lost_timestamps_;
  int predicted_frames_ = 0;  ///< sharp frames in a row bridged by the motion model
  /// Frames posed since last_frame_ without replacing it (predicted ones, blurred tracked ones).
  int gap_frames_ = 0;
  std::deque<double> recent_sharpness_;  ///< of the last kSharpnessWindow sharp frames
  int blurred_run_ = 0;                   ///< blurred frames in a row
  int matches_inliers_ = 0;
  std::vector<FrameRecord> records_;
  /// The previous segment's last keyframes (features kept) a new segment may be re-anchored to.
  std::vector<std::shared_ptr<data::KeyFrame>> anchor_candidates_;
  size_t anchor_turn_ = 0;
  int anchor_keyframes_left_ = 0;  ///< new keyframes that may still try before giving up
  /// A new segment started as soon as relocalisation gave up (after relocalization_attempts lost
  /// frames): what re-anchoring it to the segment before needs to pose those lost frames.
  struct SegmentGap {
    size_t first_record = 0;           ///< records_ index of the new segment's first frame
    double last_tracked = 0;           ///< timestamp of the previous segment's last tracked frame
    long previous_segment_kf = 0;      ///< anchor candidates from the segment before have ids >= this
    std::vector<double> lost;          ///< timestamps of the frames lost in between
  };
  std::optional<SegmentGap> segment_gap_;
};

}  // namespace tkgslam::tracking
