// Benchmarks of the per-frame hot path on real fr1_xyz images: reading a frame, ORB extraction (640x480, 1000
// features, 8 levels), frame feature construction and its radius queries, the blur measure, the input check, and descriptor matching
// between two frames; of local bundle adjustment on a synthetic window of its usual size; and of
// place recognition (vocabulary training and a keyframe-index query over 50 keyframes); and of
// loop detection for one new keyframe in maps of 50 to 400 keyframes, with and without the word index.
// Run: build/bin/tkgslam_bench   (needs ../shared next to the repository)
#include <filesystem>

#include <benchmark/benchmark.h>

#include "tkgslam/common/MallocTuning.h"
#include "tkgslam/data/Frame.h"
#include "tkgslam/data/FrameFeatures.h"
#include "tkgslam/feature/ImageSharpness.h"
#include "tkgslam/io/ConfigFile.h"
#include "tkgslam/io/TumDataset.h"
#include "tkgslam/match/OrbMatcher.h"
#include "tkgslam/loop/LoopCloser.h"
#include "tkgslam/place/KeyFrameIndex.h"
#include "tkgslam/system/FrameInput.h"
#include "SharedData.h"  // tests/
#include "loop/KeyFrameWithPoints.h"  // tests/
#include "optimize/SyntheticBundle.h"  // tests/

namespace {

using namespace tkgslam;

struct Fixture {
  SlamConfig config;
  std::unique_ptr<camera::PinholeCamera> camera;
  std::unique_ptr<feature::OrbExtractor> extractor;
  std::filesystem::path seq;  ///< fr1_xyz
  io::RgbdImages a, b;
  bool ok = false;

  Fixture() {
    seq = test::fr1xyz();
    if (test::sharedDir().empty() || !std::filesystem::is_directory(seq)) return;
    config = io::loadConfig((test::sourceDir() / "configs/tum_fr1.yaml").string());
    camera = std::make_unique<camera::PinholeCamera>(config.camera);
    extractor = std::make_unique<feature::OrbExtractor>(config.orb);
    io::TumDataset ds(seq.string());
    a = ds.load(100);
    b = ds.load(101);
    ok = true;
  }
};

Fixture& fixture() {
  static Fixture f;
  return f;
}

// Reading one frame from disk: PNG decoding of colour and 16-bit depth, grey conversion, depth to metres.
void BM_FrameLoad(benchmark::State& state) {
  auto& f = fixture();
  if (!f.ok) return state.SkipWithError("../shared/datasets/rgbd_dataset_freiburg1_xyz not found");
  const io::TumDataset ds(f.seq.string());
  int i = 0;
  for (auto _ : state) benchmark::DoNotOptimize(ds.load(100 + (i++ % 50)));
}
BENCHMARK(BM_FrameLoad)->Unit(benchmark::kMillisecond);

void BM_OrbExtraction(benchmark::State& state) {
  auto& f = fixture();
  if (!f.ok) return state.SkipWithError("../shared/datasets/rgbd_dataset_freiburg1_xyz not found");
  for (auto _ : state) benchmark::DoNotOptimize(f.extractor->extract(f.a.gray));
}
BENCHMARK(BM_OrbExtraction)->Unit(benchmark::kMillisecond);

// Boxes over 60 % of the image: the whole budget again outside them, by a second extraction
// and from the first one's kept detections (what the dynamic modes do).
cv::Mat boxSkipMask(const cv::Mat& gray) {
  cv::Mat skip = cv::Mat::zeros(gray.size(), CV_8U);
  skip(cv::Rect(0, 0, gray.cols * 6 / 10, gray.rows)).setTo(255);
  return skip;
}

void BM_OrbRefillByExtraction(benchmark::State& state) {
  auto& f = fixture();
  if (!f.ok) return state.SkipWithError("../shared/datasets/rgbd_dataset_freiburg1_xyz not found");
  const cv::Mat skip = boxSkipMask(f.a.gray);
  for (auto _ : state) benchmark::DoNotOptimize(f.extractor->extract(f.a.gray, skip));
}
BENCHMARK(BM_OrbRefillByExtraction)->Unit(benchmark::kMillisecond);

void BM_OrbRefillFromDetections(benchmark::State& state) {
  auto& f = fixture();
  if (!f.ok) return state.SkipWithError("../shared/datasets/rgbd_dataset_freiburg1_xyz not found");
  const cv::Mat skip = boxSkipMask(f.a.gray);
  feature::OrbDetections detections;
  const auto first = f.extractor->extract(f.a.gray, {}, &detections);
  for (auto _ : state) benchmark::DoNotOptimize(f.extractor->extractAgain(detections, f.a.gray, skip, first));
}
BENCHMARK(BM_OrbRefillFromDetections)->Unit(benchmark::kMillisecond);

void BM_FrameFeatures(benchmark::State& state) {
  auto& f = fixture();
  if (!f.ok) return state.SkipWithError("../shared/datasets/rgbd_dataset_freiburg1_xyz not found");
  const auto orb = f.extractor->extract(f.a.gray);
  for (auto _ : state) {
    benchmark::DoNotOptimize(data::makeFrameFeatures(orb, f.a.bgr, f.a.depth_m, *f.camera, f.config.depth));
  }
}
BENCHMARK(BM_FrameFeatures)->Unit(benchmark::kMillisecond);

// Tracking's radius queries (search by projection): one per keypoint of a real frame, 15 px, on
// the next frame's features; within one level either side, as the projection search asks.
void BM_FeaturesInArea(benchmark::State& state) {
  auto& f = fixture();
  if (!f.ok) return state.SkipWithError("../shared/datasets/rgbd_dataset_freiburg1_xyz not found");
  const auto a = data::makeFrameFeatures(f.extractor->extract(f.a.gray), f.a.bgr, f.a.depth_m, *f.camera, f.config.depth);
  const auto b = data::makeFrameFeatures(f.extractor->extract(f.b.gray), f.b.bgr, f.b.depth_m, *f.camera, f.config.depth);
  size_t found = 0;
  for (auto _ : state) {
    found = 0;
    for (const auto& kp : a->ideal) found += b->featuresInArea(kp.pt.x, kp.pt.y, 15.f, std::max(kp.octave - 1, 0), kp.octave + 1).size();
  }
  state.counters["found_per_query"] = double(found) / double(a->size());
}
BENCHMARK(BM_FeaturesInArea)->Unit(benchmark::kMicrosecond);

void BM_ImageSharpness(benchmark::State& state) {
  auto& f = fixture();
  if (!f.ok) return state.SkipWithError("../shared/datasets/rgbd_dataset_freiburg1_xyz not found");
  for (auto _ : state) benchmark::DoNotOptimize(feature::imageSharpness(f.a.gray));
}
BENCHMARK(BM_ImageSharpness)->Unit(benchmark::kMillisecond);

// The check of every frame processFrame takes (types, sizes, non-finite depths): arg 0 a frame as
// TumDataset loads it, arg 1 one without its grey image (made from BGR).
void BM_CheckFrameImages(benchmark::State& state) {
  auto& f = fixture();
  if (!f.ok) return state.SkipWithError("../shared/datasets/rgbd_dataset_freiburg1_xyz not found");
  io::RgbdImages frame = f.a;
  if (state.range(0) == 1) frame.gray.release();
  const cv::Size size(f.camera->width(), f.camera->height());
  for (auto _ : state) benchmark::DoNotOptimize(checkFrameImages(frame, size, std::nullopt));
}
BENCHMARK(BM_CheckFrameImages)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

void BM_DescriptorMatching(benchmark::State& state) {
  auto& f = fixture();
  if (!f.ok) return state.SkipWithError("../shared/datasets/rgbd_dataset_freiburg1_xyz not found");
  auto fa = data::makeFrameFeatures(f.extractor->extract(f.a.gray), f.a.bgr, f.a.depth_m, *f.camera, f.config.depth);
  auto fb = data::makeFrameFeatures(f.extractor->extract(f.b.gray), f.b.bgr, f.b.depth_m, *f.camera, f.config.depth);
  data::KeyFrame kf(0, 0, 0.0, fa, Pose::Identity());
  for (int i = 0; i < fa->size(); ++i) {
    kf.map_points[i] = std::make_shared<data::MapPoint>(i, Vec3::Zero(), &kf, fa->descriptors.row(i));
  }
  data::Frame frame(1, 0.0, fb);
  match::OrbMatcher matcher(*f.camera, f.extractor->pyramid(), f.config.depth.baseline_fx);
  std::vector<std::shared_ptr<data::MapPoint>> matches;
  int n = 0;
  for (auto _ : state) n = matcher.searchByDescriptors(kf, frame, matches);
  state.counters["matches"] = n;
}
BENCHMARK(BM_DescriptorMatching)->Unit(benchmark::kMillisecond);

// Local mapping's bundle adjustment (robust pass, outlier removal, second pass) on 10 keyframes
// (2 fixed) and 600 points seen by all, a third of the observations without depth.
void solveEachIteration(benchmark::State& state, const test::SyntheticBundle& s) {
  for (auto _ : state) {
    auto problem = s.problem;
    benchmark::DoNotOptimize(optimize::solveBundle(problem, s.K, {}));
  }
  state.counters["dense_schur"] = optimize::prefersDenseSchur(s.problem);
}

void BM_LocalBundleAdjustment(benchmark::State& state) {
  solveEachIteration(state, test::makeSyntheticBundle(10, 600, 0.05));
}
BENCHMARK(BM_LocalBundleAdjustment)->Unit(benchmark::kMillisecond);

// The window of a long run in a small scene (fr1_xyz late on: every keyframe covisible with every
// other, ~60 free keyframes in local BA): 60 keyframes (2 fixed), 440 points seen by all.
void BM_LocalBundleAdjustmentCovisible60(benchmark::State& state) {
  solveEachIteration(state, test::makeSyntheticBundle(60, 440, 0.05, 0.01, 0.002));
}
BENCHMARK(BM_LocalBundleAdjustmentCovisible60)->Unit(benchmark::kMillisecond);

// Descriptors of 50 fr1_xyz frames 15 apart: a map's worth of keyframes (the whole sequence's
// map has ~51).
struct PlaceFixture {
  std::vector<cv::Mat> keyframes;
  cv::Mat all, query;
  PlaceFixture() {
    auto& f = fixture();
    if (!f.ok) return;
    io::TumDataset ds(f.seq.string());
    for (size_t i = 0; i < 50; ++i) keyframes.push_back(f.extractor->extract(ds.load(i * 15).gray).descriptors);
    cv::vconcat(keyframes, all);
    query = f.extractor->extract(f.b.gray).descriptors;
  }
};

PlaceFixture& placeFixture() {
  static PlaceFixture p;
  return p;
}

void BM_VocabularyTraining(benchmark::State& state) {
  auto& p = placeFixture();
  if (p.keyframes.empty()) return state.SkipWithError("../shared/datasets/rgbd_dataset_freiburg1_xyz not found");
  int words = 0;
  for (auto _ : state) words = place::Vocabulary::train(p.all).words();
  state.counters["descriptors"] = p.all.rows;
  state.counters["words"] = words;
}
BENCHMARK(BM_VocabularyTraining)->Unit(benchmark::kMillisecond);

void BM_KeyFrameIndexQuery(benchmark::State& state) {
  auto& p = placeFixture();
  if (p.keyframes.empty()) return state.SkipWithError("../shared/datasets/rgbd_dataset_freiburg1_xyz not found");
  const place::KeyFrameIndex index(place::Vocabulary::train(p.all), p.keyframes);
  for (auto _ : state) benchmark::DoNotOptimize(index.query(p.query, 20));
}
BENCHMARK(BM_KeyFrameIndexQuery)->Unit(benchmark::kMillisecond);

// Loop detection for the newest keyframe of a map of range(0) keyframes (fr1_xyz frames spread
// over the sequence, at the identity pose, no two sharing a point, so every older one is a
// candidate), matching every candidate (range(1) = 0) or the 50 most similar by words (50). Any
// loop found is taken as consistent with the map (huge min_correction), so the map is never
// changed and each iteration does the same work. The word index is trained before timing.
void BM_LoopDetection(benchmark::State& state) {
  auto& f = fixture();
  if (!f.ok) return state.SkipWithError("../shared/datasets/rgbd_dataset_freiburg1_xyz not found");
  const int n = int(state.range(0));
  SlamConfig config = f.config;
  config.deterministic = true;
  config.loop.word_candidates = int(state.range(1));
  config.loop.min_correction_m = 1e9;
  config.loop.min_correction_deg = 1e9;
  data::Map map;
  io::TumDataset ds(f.seq.string());
  std::shared_ptr<data::KeyFrame> newest;
  for (int k = 0; k < n; ++k) {
    const int i = int(k * (ds.size() - 1) / n);
    const auto images = ds.load(i);
    auto features = data::makeFrameFeatures(f.extractor->extract(images.gray), images.bgr, images.depth_m, *f.camera,
                                            config.depth);
    newest = test::addKeyFrameWithPoints(map, features, i, images.timestamp, Pose::Identity(), *f.camera,
                                         f.extractor->pyramid());
  }
  loop::LoopCloser closer(map, *f.camera, f.extractor->pyramid(), config);
  closer.process(newest);  // trains the word index
  for (auto _ : state) closer.process(newest);
  const auto& s = closer.stats();
  state.counters["matched_per_keyframe"] = double(s.candidates_considered) / s.keyframes_checked;
}
BENCHMARK(BM_LoopDetection)
    ->ArgsProduct({{50, 200, 400}, {0, 50}})
    ->ArgNames({"keyframes", "words"})
    ->Unit(benchmark::kMillisecond);

}  // namespace

// The CLI's malloc settings: without them the per-frame image buffers are faulted in again on
// every iteration (reading a frame 14.6 instead of 4.4 ms, the blur measure 8.1 instead of 0.19 ms).
int main(int argc, char** argv) {
  tkgslam::common::tuneMallocForFrames();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
