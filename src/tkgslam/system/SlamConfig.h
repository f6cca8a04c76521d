#pragma once
// Aggregated configuration of the whole system, one struct per module.
#include <cstdint>
#include <string>

#include "tkgslam/camera/DepthParams.h"
#include "tkgslam/camera/PinholeCamera.h"
#include "tkgslam/dynamic/BoxTracker.h"
#include "tkgslam/dynamic/DynamicFilter.h"
#include "tkgslam/dynamic/YoloDetector.h"
#include "tkgslam/feature/OrbExtractor.h"

namespace tkgslam {


struct TrackingParams {
  int min_init_features = 500;     ///< keypoints with depth needed to start a map
  int min_tracked_inliers = 30;    ///< below this after local-map tracking, the frame is lost
  int max_frames_between_keyframes = 30;  ///< 0 = camera fps
  int relocalization_attempts = 5; ///< lost frames before a new map segment is started
  /// Keyframes of a loaded map a lost frame is tried against: the most similar ones by their
  /// words (place::KeyFrameIndex). 0 = every keyframe, newest first, as before the index.
  int relocalization_candidates = 20;
  /// Untrackable frames in a row given the constant-velocity prediction (marked "predicted" in
  /// frame_log.txt) before the camera counts as lost; 0 = lost at the first one (ORB-SLAM2).
  int max_predicted_frames = 3;
  /// Move a new map segment into the previous one's frame once it sees the same scene again.
  bool reanchor_segments = true;
  /// A frame whose sharpness (feature::imageSharpness) is below this share of the median of the
  /// last frames counts as blurred: it makes no keyframe and is not matched against (the frame
  /// before it is), and when it cannot be tracked its prediction does not count against
  /// max_predicted_frames. 0 = off.
  double blur_ratio = 0.3;
  /// A tracked pose that differs from the constant-velocity prediction by more than this rotation
  /// (degrees) or camera-centre distance (metres) in one frame is a jump no hand-held camera makes
  /// (the TUM ground truth: at most 3 deg / 1 cm per 30 Hz frame): wrong matches (e.g. a person
  /// the detector missed) won the optimisation. The frame is treated as untrackable instead.
  /// After n bridged frames the limits are n + 1 times these. <= 0 = off.
  double max_jump_deg = 6.0;
  double max_jump_m = 0.1;
  /// A frame whose dynamic-object boxes cover at least this share of the image (a person filling
  /// the view) is expected to fail like a blurred one: when it cannot be tracked, its prediction
  /// does not count against max_predicted_frames either. > 1 = off.
  double covered_ratio = 0.9;
  /// A frame that only the keypoints the geometry check re-admitted inside the boxes can track
  /// (too few matches outside them) needs at least this many local-map inliers, else it is treated
  /// as untrackable, and it makes no keyframe: the check re-admitted them using the predicted
  /// pose, so the tracked pose has no independent support. 0 = off: such frames are like any
  /// other. Off by default: 60 helps synchronous TKG on the extreme composites a lot but makes the
  /// lookahead modes lose tracking more often (bench/results/extreme_sensitivity_300.md).
  int min_rescued_inliers = 0;
  /// At the end of a run (and for frames older than Tracker::kPoseCheckWindow), each tracked frame's
  /// pose is checked against the map as it then is: where the pose its own inlier matches give in
  /// that map is further than this (metres, camera centre) from the stored one - the frame was
  /// tracked wrong, e.g. on a person the detector missed, and bundle adjustment later corrected the
  /// points but not the keyframe the frame is stored against - that pose replaces it. 0 = off.
  double pose_check_m = 0.02;
  /// Last, a run of at most Tracker::kExcursionFrames frames whose camera centres are all further
  /// than this (metres) from the straight line between the frames either side - out and back within
  /// a tenth of a second, more than a hand-held camera moves - gets poses interpolated between those
  /// two. 0 = off.
  double excursion_m = 0.03;
};

struct MappingParams {
  int local_ba_iterations = 10;
  int covisible_keyframes = 10;    ///< neighbours used for fusion
  double keyframe_redundancy = 0.9;  ///< cull a keyframe when this share of its points is seen elsewhere
  bool cull_keyframes = true;
  /// A local BA that moves its new keyframe further than this from where tracking put it
  /// (metres, degrees) is solved again with the keyframe held there. On the static fr1_xyz no
  /// keyframe moves more than 0.9 cm / 0.4 deg; on the composites the bundle moved new keyframes
  /// whose view is mostly on people (weakly constrained) up to 14 cm / 8.5 deg. Off
  /// by default: where tracking itself was off, holding the keyframe keeps the error (TKG helped,
  /// TKGt hurt on the composites; bench/results/keyframe_hold_300.md). <= 0 = off; e.g. 0.03 / 1.5.
  double max_keyframe_shift_m = 0;
  double max_keyframe_shift_deg = 0;
};

/// Loop closing (ORB-SLAM2's LoopClosing for RGB-D, without a vocabulary): each new keyframe is
/// matched against the older keyframes it shares no map points with; when it and one of the next
/// keyframes find the camera far from where the map has it, the keyframes are corrected by an
/// SE(3) pose graph and the two sides' points fused. See loop::LoopCloser.
struct LoopParams {
  bool enabled = true;
  /// Close only once a later keyframe finds the same correction: where the old map is itself
  /// off (people over the first frames), single detections pulled it further off.
  bool confirm = true;
  /// ... one of the next this many keyframes (1 = the next one only); those in between that find
  /// no loop (a person in front, a blurred image) do not cancel the detection.
  int confirm_within = 3;
  int min_inliers = 40;         ///< PnP + pose-optimisation inliers against the old keyframe
  int min_keyframe_gap = 10;    ///< candidates are at least this many keyframes older
  int candidates = 3;           ///< old keyframes verified per new keyframe (best by descriptor matches)
  /// Where more old keyframes than this are candidates, only this many most like the new keyframe
  /// by visual words (place::KeyFrameDatabase) are matched by descriptors, so the search does not
  /// grow with the map (0 = match every candidate).
  int word_candidates = 50;
  double min_correction_m = 0.05;   ///< smaller disagreements are left to local BA
  double min_correction_deg = 3.0;  ///< ... in rotation (degrees)
  /// Bundle adjustment over every keyframe and point after a closure (0 = none): the pose graph
  /// moves keyframes rigidly with their points; this refits both to the observations across the
  /// closed loop.
  int global_ba_iterations = 10;
};

/// Dynamic-object handling, the paper's ablations (Table 3):
/// orb = none (ORB-SLAM2 baseline); T = drop every keypoint in a box; TK = T + Kalman filling of
/// missed detections; TG = T + multi-view geometry when boxes cover >= tau; TKG = all.
enum class DynamicMode { Orb, T, TK, TG, TKG };
const char* toString(DynamicMode mode);
/// Parses "orb", "T", "TK", "TG", "TKG" (case-insensitive); throws InputError otherwise.
DynamicMode parseDynamicMode(const std::string& text);

struct DynamicParams {
  DynamicMode mode = DynamicMode::Orb;
  dynamic::DetectorParams detector;
  dynamic::BoxTrackerParams tracker;
  dynamic::GeometryParams geometry;
  int detect_every = 1;  ///< run the detector on every N-th frame; the Kalman tracker predicts between
  double box_margin = 0.05;  ///< boxes are widened by this fraction of their size on each side
  /// Exclude only the part of each box that may be the object (by depth, see objectMaskInBoxes)
  /// instead of the whole box; the geometry check then works on that part. Not in the paper.
  bool object_mask = false;
  dynamic::ObjectMaskParams object;
  int detector_latency = 0;  ///< frames until a detection is used (0 = wait for it; see BoxPipeline)
  /// Kalman modes: tracks' boxes also follow optical flow between frames. "auto" = only when some
  /// frames are tracked without a detection of their own: the detector skips frames, tiles them, or
  /// its result arrives late without lookahead (with a detection on every frame the flow only moves
  /// missed boxes and did not pay for its ~1 ms there; run --fast: bench/results/detector_input_300.md).
  std::string box_flow = "auto";
  /// Asynchronous detection: erase the map points that keyframes created inside the boxes of a
  /// detection that arrived late (see SlamSystem::cullLateDynamicPoints).
  bool late_culling = true;
  /// Kalman modes with N > 1 or L > 0: hold each frame back until the next detection after it is
  /// known, so that its boxes are interpolated between detections instead of extrapolated (see
  /// BoxPipeline). Poses come out lookaheadDelay() frames late; throughput is unchanged.
  bool lookahead = false;
  /// Lookahead only: frames tiled into one detector input (1 = one full-size frame per run; 4 = the
  /// detect_every-th frames are detected in groups of 4 at half resolution, one run per group).
  int detector_tiles = 1;
  /// Boxes cover at least this share of the image: ORB features are extracted again outside them,
  /// so the whole feature budget goes to what may be static (0 = off; every mode with boxes).
  double refill_ratio = 0.4;
  /// Not every frame is detected synchronously: frames skipped, tiled, or detected late (what
  /// lookahead can hold frames back for).
  bool sparseDetection() const { return detect_every > 1 || detector_latency > 0 || detector_tiles > 1; }
  bool usesLookahead() const { return lookahead && usesKalman() && sparseDetection(); }
  int usesTiles() const { return usesLookahead() ? detector_tiles : 1; }
  /// Lookahead: the most frames a frame waits for its boxes (N x tiles + L - 1).
  int lookaheadDelay() const { return usesLookahead() ? detect_every * usesTiles() + detector_latency - 1 : 0; }
  /// Some frames are tracked with predicted, not detected, boxes: sparse detection, unless lookahead
  /// holds every frame back until its own detection (one frame per run, none skipped).
  bool framesWithoutOwnDetection() const {
    return sparseDetection() && !(usesLookahead() && detect_every == 1 && detector_tiles == 1);
  }
  bool usesBoxFlow() const {
    return usesKalman() && (box_flow == "on" || (box_flow == "auto" && framesWithoutOwnDetection()));
  }
  bool usesKalman() const { return mode == DynamicMode::TK || mode == DynamicMode::TKG; }
  bool usesGeometry() const { return mode == DynamicMode::TG || mode == DynamicMode::TKG; }
};

struct SlamConfig {
  std::string source;  ///< file the config came from
  camera::CameraParams camera;
  DepthParams depth;
  feature::OrbParams orb;
  TrackingParams tracking;
  MappingParams mapping;
  LoopParams loop;
  DynamicParams dynamic;
  bool deterministic = false;
  std::uint64_t seed = 42;
  /// Threads of OpenCV's own pool (process-wide: cv::setNumThreads); 0 = OpenCV's default. 1 keeps
  /// an asynchronous detector on one core, leaving the other to tracking and mapping.
  int opencv_threads = 0;
  /// Largest opencv_threads accepted (a million made the thread pool hang, INT_MAX crash).
  static constexpr int kMaxOpenCvThreads = 256;
};

}  // namespace tkgslam
