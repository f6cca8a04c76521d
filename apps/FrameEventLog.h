#pragma once
// frame_log.txt of `tkgslam run`: one line per frame without a tracked pose, and per other event
// (predicted, interpolated, blurred, new segment, re-anchored, skipped), with their counts.
#include <filesystem>
#include <string>

#include "tkgslam/io/OutputFile.h"
#include "tkgslam/system/SlamSystem.h"

namespace tkgslam::app {

class FrameEventLog {
 public:
  /// Creates the file (with its header line). Throws InputError if it cannot be written.
  explicit FrameEventLog(const std::filesystem::path& path);

  /// Logs a tracked (or not) frame's events; with lookahead it arrives some frames after the frame.
  void add(const FrameOutcome& f);
  /// A frame that could not be read (`timestamp` in seconds).
  void addSkipped(double timestamp, const std::string& why);
  /// Closes the file; throws InputError if anything could not be written (disk full).
  void finish() { out_.finish(); }

  /// How many of each event were logged.
  struct Counts {
    int lost = 0;          ///< frames without a pose (not initialised yet, or lost)
    int interpolated = 0;  ///< lost frames posed by interpolation once relocalised
    int predicted = 0;     ///< frames posed by the motion model
    int blurred = 0;
    int segments = 0;      ///< new map segments
    int reanchored = 0;    ///< segments moved into the previous one's frame
    int skipped = 0;       ///< frames that could not be read
  };
  const Counts& counts() const { return counts_; }
  /// Why the first skipped frame could not be read; empty when none was skipped.
  const std::string& firstSkipReason() const { return first_skip_reason_; }

 private:
  io::OutputLog out_;
  Counts counts_;
  std::string first_skip_reason_;
};

}  // namespace tkgslam::app
