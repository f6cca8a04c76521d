#pragma once
// The RGB-D SLAM pipeline for one sequence: feature extraction, tracking, local mapping (on its
// own thread unless deterministic), and the outputs (trajectories, map, timings).
#include <memory>
#include <string>
#include <vector>

#include "tkgslam/camera/PinholeCamera.h"
#include "tkgslam/data/Map.h"
#include "tkgslam/feature/OrbExtractor.h"
#include "tkgslam/io/PlyWriter.h"
#include "tkgslam/io/TumDataset.h"
#include "tkgslam/mapping/LocalMapper.h"
#include "tkgslam/mapping/LocalMappingThread.h"
#include "tkgslam/system/SlamConfig.h"
#include "tkgslam/system/TimingStats.h"
#include "tkgslam/tracking/Tracker.h"

namespace tkgslam {

class SlamSystem {
 public:
  /// Throws InputError for an invalid configuration.
  explicit SlamSystem(const SlamConfig& config);
  ~SlamSystem();

  /// Processes one RGB-D frame; returns what tracking made of it.
  tracking::TrackResult processFrame(const io::RgbdImages& images);
  /// Waits for local mapping to finish the queued keyframes.
  void finish();

  /// Camera-to-world poses of every tracked frame, with the latest keyframe corrections.
  std::vector<StampedPose> trajectory() const;
  /// Camera-to-world poses of the keyframes still in the map.
  std::vector<StampedPose> keyFrameTrajectory() const;
  std::vector<io::ColouredPoint> mapPoints() const;
  size_t keyFrameCount() const;
  size_t mapPointCount() const;
  int framesProcessed() const { return frames_; }
  int framesTracked() const { return int(tracker_->records().size()); }
  tracking::TrackingState state() const { return tracker_->state(); }
  const TimingStats& timing() const { return timing_; }
  const SlamConfig& config() const { return config_; }

 private:
  SlamConfig config_;
  camera::PinholeCamera camera_;
  feature::OrbExtractor extractor_;
  mutable data::Map map_;
  std::unique_ptr<tracking::Tracker> tracker_;
  std::unique_ptr<mapping::LocalMapper> mapper_;
  std::unique_ptr<mapping::LocalMappingThread> mapping_thread_;
  TimingStats timing_;
  int frames_ = 0;
};

}  // namespace tkgslam
