// Benchmarks of the dynamic-object modules on real images: the YOLOv5n detector at the input sizes
// the CLI offers (the export's letterboxed 640 x 640 square, the fitted 640 x 480 default, 320 x 256
// and 256 x 192 from --detector-size) and with four frames tiled into one run (--fast); the Kalman box
// tracker; and the box mask of a frame whose boxes cover ~60 % of the view, whole boxes and the
// object mask by depth region. The detector's numbers are what the run's `detector` timing shows when
// nothing else runs (in a run it shares the cores with ORB extraction).
// Run: build/bin/tkgslam_bench --benchmark_filter='Yolo|BoxTracker|BoxMask'   (needs ../shared)
#include <filesystem>
#include <memory>

#include <benchmark/benchmark.h>
#include <opencv2/imgcodecs.hpp>

#include "tkgslam/dynamic/BoxTracker.h"
#include "tkgslam/dynamic/DynamicFilter.h"
#include "tkgslam/dynamic/YoloDetector.h"
#include "tkgslam/io/TumDataset.h"
#include "SharedData.h"  // tests/

namespace {

using namespace tkgslam;

/// A 640 x 480 frame of the real fr3_walking_xyz sequence with people in it (../shared/datasets/people).
const cv::Mat& peopleFrame() {
  static const cv::Mat image =
      test::sharedDir().empty() ? cv::Mat()
                                 : cv::imread((test::sharedDir() / "datasets/people/fr3_walking_xyz_1341846313.592026.png").string(),
                                              cv::IMREAD_COLOR);
  return image;
}

void BM_YoloDetect(benchmark::State& state) {
  const std::string model = test::yoloModel();
  if (peopleFrame().empty() || !std::filesystem::is_regular_file(model)) {
    return state.SkipWithError("../shared (people photos, YOLOv5n model) not found");
  }
  dynamic::DetectorParams params;
  params.model = model;
  params.input_size = int(state.range(0));
  params.fit_input = state.range(1) != 0;
  const int tiles = int(state.range(2));
  dynamic::YoloDetector detector(params);
  const std::vector<cv::Mat> images(size_t(tiles), peopleFrame());
  detector.detectTiles(images);  // the first run at this size reloads the net
  size_t boxes = 0;
  for (auto _ : state) boxes = detector.detectTiles(images).front().size();
  const cv::Size input = detector.inputSize();
  state.SetLabel(std::to_string(input.width) + "x" + std::to_string(input.height) + ", " + std::to_string(tiles) +
                 " frame(s), " + std::to_string(boxes) + " box(es) in the first");
}
// {long side, fitted to the image's aspect ratio, frames tiled into one run}
BENCHMARK(BM_YoloDetect)
    ->Args({640, 0, 1})
    ->Args({640, 1, 1})
    ->Args({320, 1, 1})
    ->Args({256, 1, 1})
    ->Args({640, 1, 4})
    ->Unit(benchmark::kMillisecond);

/// Four people crossing a 640 x 480 view, each detected on the frames where (frame + person) % 5 != 0.
std::vector<dynamic::Detection> walkingPeople(int frame) {
  std::vector<dynamic::Detection> out;
  for (int p = 0; p < 4; ++p) {
    if ((frame + p) % 5 == 0) continue;  // missed: the tracker fills it in
    dynamic::Detection d;
    d.box = cv::Rect2f(float((40 + 130 * p + 6 * frame) % 560), float(60 + 10 * p), 120.f, 380.f - 20.f * p);
    d.score = 0.8f;
    out.push_back(d);
  }
  return out;
}

void BM_BoxTrackerUpdate(benchmark::State& state) {
  std::vector<std::vector<dynamic::Detection>> frames;
  for (int f = 0; f < 100; ++f) frames.push_back(walkingPeople(f));
  const cv::Size image(640, 480);
  for (auto _ : state) {
    dynamic::BoxTracker tracker;
    for (const auto& dets : frames) benchmark::DoNotOptimize(tracker.update(dets, image));
  }
  state.SetItemsProcessed(state.iterations() * int64_t(frames.size()));  // items = frames
}
BENCHMARK(BM_BoxTrackerUpdate)->Unit(benchmark::kMicrosecond);

/// Boxes over ~60 % of a real fr1_xyz frame: whole boxes (0) or the object mask by depth region (1).
void BM_BoxMask(benchmark::State& state) {
  if (test::sharedDir().empty() || !std::filesystem::is_directory(test::fr1xyz())) {
    return state.SkipWithError("../shared/datasets/rgbd_dataset_freiburg1_xyz not found");
  }
  static const io::RgbdImages frame = io::TumDataset(test::fr1xyz().string()).load(100);
  std::vector<dynamic::Detection> boxes(3);
  boxes[0].box = cv::Rect2f(20, 40, 130, 420);
  boxes[1].box = cv::Rect2f(250, 20, 120, 450);
  boxes[2].box = cv::Rect2f(460, 80, 130, 390);
  dynamic::ObjectMaskParams object;
  object.region = true;
  const dynamic::ObjectMaskParams* use = state.range(0) ? &object : nullptr;
  double ratio = 0;
  for (auto _ : state) ratio = dynamic::dynamicMask(boxes, frame.bgr, frame.depth_m, 0.05, use).ratio;
  state.SetLabel(std::string(use ? "object region" : "whole boxes") + ", T = " + std::to_string(ratio).substr(0, 4));
}
BENCHMARK(BM_BoxMask)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);

}  // namespace
