#include "FrameEventLog.h"

#include <fmt/format.h>


namespace tkgslam::app {

FrameEventLog::FrameEventLog(const std::filesystem::path& path) : out_(path.string(), "frame log") {
  out_.write("# frames without a tracked pose, and other events: timestamp status reason\n");
}

void FrameEventLog::add(const FrameOutcome& f) {
  using tracking::TrackingState;
  if (!f.result.tracked) {
    ++counts_.lost;
    const bool uninit = f.state == TrackingState::NotInitialized;
    out_.write(fmt::format("{:.6f} {} {}\n", f.timestamp, uninit ? "not_initialised" : "lost",
                           uninit ? "too few keypoints with depth to start a map"
                                  : "too few matches to track or relocalise"));
  }
  for (double t : f.result.interpolated_lost) {
    ++counts_.interpolated;
    out_.write(fmt::format(
        "{:.6f} interpolated lost, then posed between the frames tracked either side (found again at {:.6f})\n", t,
        f.timestamp));
  }
  if (f.result.predicted) {
    ++counts_.predicted;
    out_.write(fmt::format("{:.6f} predicted {}: pose from the constant-velocity model\n", f.timestamp,
                           f.result.jump_rejected ? "the tracked pose jumped"
                           : f.result.covered     ? "too few matches outside the boxes covering the view"
                                                  : "too few matches"));
  }
  if (f.result.blurred) {
    ++counts_.blurred;
    out_.write(fmt::format("{:.6f} blurred the image is much less sharp than the frames before: no keyframe\n",
                           f.timestamp));
  }
  if (f.result.new_segment) {
    ++counts_.segments;
    out_.write(fmt::format("{:.6f} new_segment a new map segment starts here\n", f.timestamp));
  }
  if (f.result.reanchored) {
    ++counts_.reanchored;
    out_.write(fmt::format("{:.6f} reanchored the map segment was moved into the previous segment's frame\n",
                           f.timestamp));
  }
}

void FrameEventLog::addSkipped(double timestamp, const std::string& why) {
  if (counts_.skipped++ == 0) first_skip_reason_ = why;
  out_.write(fmt::format("{:.6f} skipped {}\n", timestamp, why));
}

}  // namespace tkgslam::app
