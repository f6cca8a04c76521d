// libtkgslam in an application: RGB-D frames in, a camera pose per frame out, as they are tracked.
// The frames come from a TUM sequence's files here; a live camera fills io::RgbdImages the same way:
// `bgr` 8-bit BGR, `depth_m` float metres (0 = no depth), `timestamp` in seconds.
//
//   track_frames CONFIG SEQUENCE [MAX_FRAMES] > live.txt
//
// prints each tracked frame's pose (TUM format, camera-to-world) as soon as tracking has it. The
// final poses, refined by local BA and loop closing and with lost frames interpolated, are
// SlamSystem::trajectory() at the end: what `tkgslam run` writes. Exit code 2 for bad input.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <string>

#include <opencv2/imgcodecs.hpp>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include "tkgslam/common/Error.h"
#include "tkgslam/common/MallocTuning.h"
#include "tkgslam/io/ConfigFile.h"
#include "tkgslam/io/TrajectoryFile.h"
#include "tkgslam/io/TumDataset.h"
#include "tkgslam/system/SlamSystem.h"

namespace {

void printTracked(const std::vector<tkgslam::FrameOutcome>& outcomes) {
  for (const auto& o : outcomes) {
    if (o.result.T_wc) std::printf("%s\n", tkgslam::io::formatTumPose({o.timestamp, *o.result.T_wc}).c_str());
  }
}

}  // namespace

int main(int argc, char** argv) {
  using namespace tkgslam;
  if (argc < 3) {
    std::fprintf(stderr, "usage: %s CONFIG SEQUENCE [MAX_FRAMES]\n", argv[0]);
    return 2;
  }
  // glibc's malloc kept from faulting the frames' images in again every frame (as the tkgslam CLI).
  common::tuneMallocForFrames();
  // The library logs through spdlog (to stdout by default): to stderr here, so stdout is the poses.
  spdlog::set_default_logger(spdlog::stderr_color_mt("tkgslam"));
  try {
    const SlamConfig config = io::loadConfig(argv[1]);
    SlamSystem slam(config);
    const io::TumDataset sequence(argv[2]);  // only its list of image files
    const int frames = argc > 3 ? std::min(std::atoi(argv[3]), sequence.size()) : sequence.size();
    for (int i = 0; i < frames; ++i) {
      const io::RgbdEntry& files = sequence.entry(i);
      // What a camera driver hands over: colour, and depth in the sensor's units.
      io::RgbdImages frame;
      frame.timestamp = files.rgb_timestamp;
      frame.bgr = cv::imread(files.rgb_path, cv::IMREAD_COLOR);
      const cv::Mat raw_depth = cv::imread(files.depth_path, cv::IMREAD_UNCHANGED);
      raw_depth.convertTo(frame.depth_m, CV_32F, 1.0 / config.depth.factor);
      printTracked(slam.processFrame(frame));  // frame.gray is made from bgr
    }
    printTracked(slam.finish());
  } catch (const InputError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 2;
  }
  return 0;
}
