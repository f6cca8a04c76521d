#pragma once
// The RGB-D SLAM pipeline for one sequence: feature extraction, tracking, local mapping (on its
// own thread unless deterministic), and the outputs (trajectories, map, timings).
#include <deque>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "tkgslam/camera/PinholeCamera.h"
#include "tkgslam/data/Map.h"
#include "tkgslam/dynamic/BoxPipeline.h"
#include "tkgslam/dynamic/DynamicFilter.h"
#include "tkgslam/feature/OrbExtractor.h"
#include "tkgslam/io/PlyWriter.h"
#include "tkgslam/io/TumDataset.h"
#include "tkgslam/loop/LoopCloser.h"
#include "tkgslam/mapping/LocalMapper.h"
#include "tkgslam/mapping/LocalMappingThread.h"
#include "tkgslam/system/SlamConfig.h"
#include "tkgslam/system/TimingStats.h"
#include "tkgslam/tracking/Tracker.h"

namespace tkgslam {

/// What the dynamic filter did on one frame (for reports and debugging).
struct DynamicFrameInfo {
  double timestamp = 0;
  double box_ratio = 0;          ///< T = area(union of boxes) / image area
  int detected = 0;              ///< boxes from the detector
  int predicted = 0;             ///< boxes filled in by the Kalman tracker
  int keypoints = 0;
  int dropped = 0;               ///< keypoints excluded in the end
  int readmitted = 0;            ///< in-box keypoints the geometry check found static
  int unboxed = 0;               ///< keypoints outside the boxes the geometry check found dynamic
  int late_culled = 0;           ///< map points erased when a late detection arrived
  bool geometry = false;         ///< the multi-view check ran
  int missed_dynamic = -1;       ///< kept keypoints on the ground-truth mask (-1: no mask)
  std::vector<dynamic::Detection> boxes;
  std::vector<cv::Point2f> dropped_points;  ///< raw pixels of the excluded keypoints
};

/// Keypoint classification against ground-truth masks (composites): positive = dynamic.
struct KeypointClassification {
  long true_positive = 0;   ///< dropped, on a dynamic object
  long false_positive = 0;  ///< dropped, static
  long false_negative = 0;  ///< kept, on a dynamic object
  long true_negative = 0;
  int frames = 0;
  double precision() const {
    return true_positive + false_positive ? double(true_positive) / (true_positive + false_positive) : 0.0;
  }
  double recall() const {
    return true_positive + false_negative ? double(true_positive) / (true_positive + false_negative) : 0.0;
  }
};

/// What tracking made of one frame.
struct FrameOutcome {
  long index = 0;  ///< frames handed to processFrame before this one
  double timestamp = 0;
  tracking::TrackResult result;  ///< result.T_wc: the frame's camera-to-world pose, if tracked
  tracking::TrackingState state = tracking::TrackingState::NotInitialized;  ///< after the frame
};

class SlamSystem {
 public:
  /// Throws InputError for an invalid configuration.
  explicit SlamSystem(const SlamConfig& config);
  ~SlamSystem();

  /// Processes one RGB-D frame; returns what tracking made of the frames it tracked: this one, or
  /// with dynamic.lookahead the held-back frames whose boxes became final (possibly none).
  /// `images`: bgr 8-bit BGR and depth_m float metres at the config's image size, timestamps in
  /// seconds and increasing; gray may be left empty (see checkFrameImages). Throws InputError for a
  /// frame that is not so; the system is unchanged then and takes the next frame.
  std::vector<FrameOutcome> processFrame(const io::RgbdImages& images);
  /// Tracks the frames still held back (lookahead) and waits for local mapping to finish the
  /// queued keyframes; returns the outcomes of the frames tracked here.
  std::vector<FrameOutcome> finish();

  /// Starts this run in a map saved by an earlier one (io/MapFile.h): its keyframes and points
  /// become this run's map, and tracking first relocalises against them (Tracker::startInLoadedMap),
  /// so the poses come out in that map's world frame. Call before the first frame. Returns the
  /// number of keyframes read. Throws InputError (missing or corrupt file, another camera).
  /// `localization_only`: the run tracks in the map without changing it (no keyframes, points or
  /// segments of its own; local mapping and loop closing get nothing to do).
  size_t loadMap(const std::string& path, bool localization_only = false);
  /// Saves the active map for a later run's loadMap (call after finish()). Throws InputError.
  void saveMap(const std::string& path) const;

  /// Camera-to-world poses of every tracked frame, with the latest keyframe corrections.
  std::vector<StampedPose> trajectory() const;
  /// Camera-to-world poses of this run's keyframes still in the map (not those of a loaded map).
  std::vector<StampedPose> keyFrameTrajectory() const;
  std::vector<io::ColouredPoint> mapPoints() const;
  size_t keyFrameCount() const;
  size_t mapPointCount() const;
  int framesProcessed() const { return frames_; }
  int framesTracked() const { return int(tracker_->records().size()); }
  tracking::TrackingState state() const { return tracker_->state(); }
  const TimingStats& timing() const { return timing_; }
  /// Loop closing so far (zeros with loop.enabled off). Read after finish() in threaded runs.
  loop::LoopStats loopStats() const { return loop_closer_ ? loop_closer_->stats() : loop::LoopStats{}; }
  /// Local mapping's counters (read after the run: the mapping thread writes them).
  mapping::MappingStats mappingStats() const { return mapper_ ? mapper_->stats() : mapping::MappingStats{}; }
  const std::vector<DynamicFrameInfo>& dynamicInfo() const { return dynamic_info_; }
  /// Filled for frames that come with a truth mask.
  const KeypointClassification& classification() const { return classification_; }
  const SlamConfig& config() const { return config_; }

 private:
  SlamConfig config_;
  camera::PinholeCamera camera_;
  feature::OrbExtractor extractor_;
  mutable data::Map map_;
  std::unique_ptr<tracking::Tracker> tracker_;
  std::unique_ptr<mapping::LocalMapper> mapper_;
  std::unique_ptr<loop::LoopCloser> loop_closer_;  ///< null with loop.enabled off
  std::unique_ptr<mapping::LocalMappingThread> mapping_thread_;
  std::unique_ptr<dynamic::BoxPipeline> boxes_;  ///< detector + box tracker; null in orb mode
  std::vector<DynamicFrameInfo> dynamic_info_;
  KeypointClassification classification_;
  TimingStats timing_;
  int frames_ = 0;
  std::optional<double> last_timestamp_;  ///< of the last frame processFrame took

  /// A frame with its features, waiting for its boxes (lookahead) or tracked at once.
  struct PreparedFrame {
    long index = 0;
    io::RgbdImages images;
    std::shared_ptr<data::FrameFeatures> features;
    std::unique_ptr<feature::OrbDetections> detections;  ///< kept for the refill (dynamic modes)
    /// Feature extraction and this frame's box work (flow, late detections; with lookahead the wait
    /// for the detection before, to start the next one).
    double prepare_ms = 0;
    double orb_ms = 0;      ///< feature extraction alone (prepare_ms less the box work and its waits)
    double wait_ms = 0;     ///< waiting for a synchronous detection
    int late_culled = 0;
    std::optional<std::vector<dynamic::Detection>> boxes;  ///< lookahead: once final
  };
  std::deque<PreparedFrame> held_;  ///< lookahead: frames waiting for their boxes, oldest first

  /// Starts the frame's box work (detector launch, flow, due detections) and extracts features.
  PreparedFrame prepare(const io::RgbdImages& images);
  /// Excludes the keypoints in `boxes`, tracks, hands a new keyframe to mapping.
  FrameOutcome track(PreparedFrame& frame, std::vector<dynamic::Detection> boxes);
  /// Gives held-back frames their final boxes, then tracks those up to frame `through` in order.
  /// processFrame passes the current frame minus the lookahead delay, so one frame is tracked per
  /// call at an even pace. Released in bursts (a detection finalises up to 8 frames at once),
  /// tracking outran the threaded local mapping (very_high composite: 90 % tracked, now 97 %).
  void trackHeld(std::vector<dynamic::FrameBoxes> final_boxes, long through, std::vector<FrameOutcome>& out);
  void recordBoxTimings(const dynamic::BoxTimings& bt);
  /// This frame's boxes -> excluded keypoints; returns the geometry step for the tracker
  /// (empty unless the mode has it and the boxes cover at least tau of the image).
  tracking::RefineKeypoints filterDynamic(PreparedFrame& frame, dynamic::BoxMask& box_mask, DynamicFrameInfo& info);
  /// Boxes cover much of the image: keeps the keypoints inside them (the geometry check may find
  /// them static) and spends the whole feature budget outside them again, from the pyramid and
  /// FAST corners prepare() kept (OrbExtractor::extractAgain).
  void refillOutsideBoxes(PreparedFrame& frame, const cv::Mat& box_mask);
  /// A late (asynchronous) detection shows where people were on frames already tracked: map
  /// points that keyframes of those frames created inside the boxes are erased, so tracking
  /// stops following the people. Returns how many.
  int cullLateDynamicPoints(const std::vector<dynamic::FrameBoxes>& late, cv::Size image);
  /// Adds the frame's keypoints to classification_; returns how many on the mask were kept.
  int scoreAgainstTruth(const cv::Mat& truth, const data::FrameFeatures& features);
};

}  // namespace tkgslam
