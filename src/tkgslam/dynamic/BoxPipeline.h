#pragma once
// Where each frame's boxes of dynamic objects come from: the YOLO detector (run on its own
// thread) and the box tracker, on a fixed schedule that depends only on frame indices, so the
// result is the same however fast the threads run (deterministic mode needs nothing extra).
//
//   latency 0 (synchronous): on every detect_every-th frame the detector runs in parallel with
//     ORB extraction and tracking waits for it; the Kalman tracker predicts between runs.
//   latency L > 0 (asynchronous): the detector is started on frame k and its result is used
//     from frame k + L on (waiting only if it is not done by then). The box tracker is rewound to
//     frame k, updated with the detections and predicted forward to the current frame. Tracking
//     never waits for the detector on frames in between; boxes come from Kalman prediction.
//     The very first frame is always detected synchronously (the map must not start on people).
// With flow on, every track's box is also moved frame to frame by optical flow (BoxFlow) and the
// Kalman filter fuses that with its constant-velocity prediction; the asynchronous path replays
// the flow over the frames it rewinds (the pipeline keeps the last latency + 2 frames' pyramids).
//
//   lookahead (needs Kalman): the caller holds each frame back until the next detection after it
//     has arrived, and only then asks for its boxes (takeFinalBoxes). Frames between detections
//     k0 < k1 get the tracks' flow-and-Kalman boxes from k0, corrected linearly towards the
//     detections at k1 (the prediction's error at k1 is spread over the gap), and people first
//     detected at k1 are followed backwards by optical flow into the frames before, where they
//     were already walking in but not yet detected. Costs the poses N + L - 1 frames of delay,
//     not throughput: the detector of frame k1 still runs beside the tracking of earlier frames.
//     Finalizing a run (the flow over the frames since the last one, the Kalman updates, the
//     corrections) happens on the detector's thread right after the inference, on a copy of the
//     box tracker and of the frames' pyramids taken at launch: the tracking thread only collects
//     the boxes. The same operations in the same order, so the result does not depend on threads.
//   tiles M > 1 (lookahead only): the detect_every-th frames are detected in groups of M with one
//     detector run on an input that tiles the M frames (YoloDetector::detectTiles), started when
//     the group's last frame begins; the run's latency counts from there. M = 4 and N = 2 cost one
//     run per 8 frames like N = 8, but every second frame gets a detection (at half resolution,
//     where YOLOv5n finds large people at least as well as at full size).
#include <deque>
#include <future>
#include <memory>
#include <optional>
#include <utility>
#include <vector>

#include "tkgslam/dynamic/BoxFlow.h"
#include "tkgslam/dynamic/BoxTracker.h"
#include "tkgslam/dynamic/YoloDetector.h"

namespace tkgslam::dynamic {

struct BoxScheduleParams {
  int detect_every = 1;  ///< run the detector on frames whose index is a multiple of this
  int latency = 0;       ///< frames between starting a detection and using it (0 = same frame)
  bool use_kalman = true;  ///< false: the ablation without Kalman (boxes = last detections)
  bool use_flow = true;    ///< move the tracks' boxes by optical flow between frames (needs Kalman)
  bool lookahead = false;  ///< boxes only once the next detection is known (needs Kalman and flow)
  int tiles = 1;           ///< frames per detector run (> 1 needs lookahead)
};

/// Times of one frame's box work, milliseconds (detector_ms < 0: no detection finished).
struct BoxTimings {
  double detector_ms = -1;  ///< inference time of the detection that was consumed (its own thread)
  double wait_ms = 0;       ///< time the caller blocked waiting for the detector
  double tracker_ms = 0;    ///< Kalman / Hungarian / optical flow work (lookahead: partly on the detector's thread)
};

/// A frame index and its boxes.
using FrameBoxes = std::pair<long, std::vector<Detection>>;

class BoxPipeline {
 public:
  /// Throws InputError for a bad model or schedule (detect_every < 1, latency outside
  /// [0, detect_every x tiles], tiles outside [1, 9] or > 1 without lookahead).
  BoxPipeline(const DetectorParams& detector, const BoxTrackerParams& tracker, const BoxScheduleParams& schedule);
  ~BoxPipeline();

  /// Starts frame `index` (indices increase by one per frame): consumes a detection that is due
  /// and launches the detector on `bgr` if the schedule says so. Call before feature extraction.
  /// `depth_m` (CV_32F metres, may be empty) lets the optical flow follow the nearest surface;
  /// `gray` (8-bit, may be empty) is `bgr` in grey if the caller has it (the flow runs on grey).
  void beginFrame(long index, const cv::Mat& bgr, const cv::Mat& depth_m = {}, const cv::Mat& gray = {});
  /// The boxes for the frame begun last, clipped to the image.
  std::vector<Detection> frameBoxes(cv::Size image, BoxTimings& timings);

  /// Boxes of earlier frames, known only now that a late (asynchronous) detection arrived: one
  /// entry per frame from the detected frame to the one before the current, oldest first.
  /// Cleared by the call.
  std::vector<FrameBoxes> takeLateBoxes() { return std::move(late_boxes_); }

  /// Lookahead mode: the frames whose boxes became final with the frame begun last, oldest first
  /// (none, or every frame up to a detection that arrived). `timings`: this frame's box work.
  std::vector<FrameBoxes> takeFinalBoxes(BoxTimings& timings);
  /// Lookahead mode, end of the sequence: waits for the detection in flight, and the frames after
  /// it get the tracks' forward boxes; everything begun becomes final.
  std::vector<FrameBoxes> flush(BoxTimings& timings);
  bool lookahead() const { return schedule_.lookahead; }

 private:
  using FlowFrames = std::deque<std::pair<long, FlowFrame>>;  ///< frame index and pyramid, oldest first
  /// Lookahead: the box tracker and the last final frame, advanced by finalizing a run.
  struct Lookahead {
    BoxTracker tracker;
    long through = -1;
    std::vector<FrameBoxes> boxes;  ///< made final, oldest first
    double tracker_ms = 0;
  };
  struct Result {
    std::vector<std::vector<Detection>> per_tile;
    double detector_ms = 0;
    std::optional<Lookahead> lookahead;  ///< lookahead: the run already finalized
  };
  struct Pending {
    std::vector<long> tiles;  ///< the frames detected, oldest first
    long frame() const { return tiles.back(); }  ///< the run was started on its last tile
    std::future<Result> result;
    BoxTracker tracker_before;  ///< without lookahead: the box tracker just before frame()
  };

  /// Applies a finished detection of frame p.frame and predicts forward to just before `index`;
  /// returns the boxes of frame p.frame (the box tracker's output there).
  std::vector<Detection> consume(Pending& p, long index, cv::Size image, BoxTimings& timings);
  /// The boxes of `tracker`'s tracks moved by optical flow from frame-1 to frame (nullopt: flow
  /// off or a frame not in `frames`).
  std::optional<BoxTracker::Moved> flowTo(const FlowFrames& frames, const BoxTracker& tracker, long frame) const;
  static const FlowFrame* flowFrame(const FlowFrames& frames, long frame);
  /// Starts the detector on the frames in tile_frames_ (which it empties); with lookahead the
  /// run also finalizes its frames (on its thread, from the state at launch).
  void launch();
  /// Lookahead: waits for the run and takes the boxes it made final and the tracker after it.
  void finalize(Pending& p, BoxTimings& timings);
  /// Lookahead: the boxes of the frames after state.through up to `frame`, which has the
  /// detections `detections` (see the class comment), appended to state.boxes. Touches no
  /// member but the const flow_: runs on the detector's thread.
  void finalizeThrough(Lookahead& state, const FlowFrames& frames, long frame,
                       const std::vector<Detection>& detections, cv::Size image) const;
  /// Lookahead: predicted boxes for state.through + 1 .. last (no detection), made final.
  void predictThrough(Lookahead& state, const FlowFrames& frames, long last, cv::Size image,
                      std::vector<FrameBoxes>& out) const;
  /// Lookahead: a box first detected on frame k followed back by flow over frames k-1 .. first;
  /// one box per frame reached, newest first (stops where the flow loses it).
  std::vector<cv::Rect2f> followBack(const FlowFrames& frames, const cv::Rect2f& box, long k, long first,
                                     cv::Size image) const;

  std::unique_ptr<YoloDetector> detector_;
  BoxScheduleParams schedule_;
  BoxTracker tracker_;
  BoxFlow flow_;
  FlowFrames flow_frames_;  ///< the last frames' pyramids, oldest first
  std::vector<Detection> last_detections_;  ///< without Kalman: reused until the next detection
  std::optional<Pending> pending_;
  std::vector<std::pair<long, cv::Mat>> tile_frames_;  ///< frames waiting for the next run (BGR)
  std::vector<FrameBoxes> late_boxes_;
  std::vector<FrameBoxes> final_boxes_;  ///< lookahead: made final, not yet taken
  long final_through_ = -1;              ///< lookahead: last frame whose boxes are final
  cv::Size image_;                       ///< of the frames begun
  long index_ = -1;
  BoxTimings begin_timings_;  ///< waits in beginFrame, reported with the frame's boxes
};

}  // namespace tkgslam::dynamic
