// tkgslam run's outputs as a user relies on them.
#include <algorithm>
#include <filesystem>
#include <fstream>

#include <fmt/format.h>

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include "FaultySequence.h"
#include "TestSupport.h"
#include "tkgslam/eval/Ate.h"
#include "tkgslam/io/TrajectoryFile.h"
#include "tkgslam/io/TumDataset.h"

namespace tkgslam {
namespace {

TEST(RunCli, ConfigUsedHasTheCommandLinesOptionsAndRepeatsTheRun) {
  TKGSLAM_REQUIRE_SHARED();
  test::TempDir tmp;
  const std::string data = " -d " + test::fr1xyz().string() + " --max-frames 10 -q -o ";
  std::string out;
  ASSERT_EQ(test::runCli("run --deterministic --mode TKG --detect-every 2 --object-mask on --detector-size 320 -c " +
                             (test::sourceDir() / "configs" / "tum_fr1.yaml").string() + data + (tmp / "a").string(),
                         &out),
            0)
      << out;
  const std::string used = test::readFile(tmp / "a" / "config_used.yaml");
  EXPECT_NE(used.find("  mode: TKG\n"), std::string::npos) << used;
  EXPECT_NE(used.find("  detect_every: 2\n"), std::string::npos) << used;
  EXPECT_NE(used.find("  object_mask: true\n"), std::string::npos) << used;
  EXPECT_NE(used.find("  input_size: 320\n"), std::string::npos) << used;
  EXPECT_NE(used.find("  fit_input: true\n"), std::string::npos) << used;
  EXPECT_NE(used.find("  deterministic: true\n"), std::string::npos) << used;
  // The model path is absolute: the file lies in another folder than the config it came from.
  EXPECT_NE(used.find("  model: /"), std::string::npos) << used;

  // The same run from config_used.yaml alone, without the options: the same trajectory. (fr1_xyz has no
  // people, so this shows the file loads from anywhere - model path included; the lines above show the
  // options were applied.)
  ASSERT_EQ(test::runCli("run -c " + (tmp / "a" / "config_used.yaml").string() + data + (tmp / "b").string(), &out), 0)
      << out;
  const std::string trajectory = test::readFile(tmp / "a" / "trajectory.txt");
  EXPECT_GT(trajectory.size(), 500u);
  EXPECT_EQ(test::readFile(tmp / "b" / "trajectory.txt"), trajectory);
  // Below its first line (the file it came from), the same configuration.
  const std::string again = test::readFile(tmp / "b" / "config_used.yaml");
  EXPECT_EQ(again.substr(again.find('\n')), used.substr(used.find('\n')));

  // A detector size the network cannot take is refused before anything runs.
  EXPECT_EQ(test::runCli("run --mode TKG --detector-size 300 -c " +
                             (test::sourceDir() / "configs" / "tum_fr1.yaml").string() + data + (tmp / "c").string(),
                         &out),
            2);
  EXPECT_NE(out.find("--detector-size: must be a multiple of 32"), std::string::npos) << out;
  // So is one that would exhaust the memory.
  EXPECT_EQ(test::runCli("run --mode TKG --detector-size 16384 -c " +
                             (test::sourceDir() / "configs" / "tum_fr1.yaml").string() + data + (tmp / "c").string(),
                         &out),
            2);
  EXPECT_NE(out.find("from 64 to 2048"), std::string::npos) << out;
}

TEST(RunCli, SetOverridesAConfigKeyAndTheNamedOptionsWinOverIt) {
  TKGSLAM_REQUIRE_SHARED();
  test::TempDir tmp;
  const std::string run = "run -q --max-frames 5 -c " + (test::sourceDir() / "configs" / "tum_fr1.yaml").string() +
                          " -d " + test::fr1xyz().string() + " -o ";
  std::string out;
  ASSERT_EQ(test::runCli(run + (tmp / "a").string() +
                             " --set tracking.max_jump_m=0.05 --set loop.min_inliers=33 --set dynamic.detect_every=4"
                             " --detect-every 3",
                         &out),
            0)
      << out;
  const std::string used = test::readFile(tmp / "a" / "config_used.yaml");
  EXPECT_NE(used.find("  max_jump_m: 0.05\n"), std::string::npos) << used;
  EXPECT_NE(used.find("  min_inliers: 33\n"), std::string::npos) << used;  // a section tum_fr1.yaml has not
  EXPECT_NE(used.find("  detect_every: 3\n"), std::string::npos) << used;  // --detect-every wins
  // A typo is refused before anything runs, naming the override.
  EXPECT_EQ(test::runCli(run + (tmp / "b").string() + " --set tracking.max_jump=0.05", &out), 2);
  EXPECT_NE(out.find("--set 'tracking.max_jump=0.05': unknown key 'tracking.max_jump'"), std::string::npos) << out;
  EXPECT_FALSE(std::filesystem::exists(tmp / "b" / "trajectory.txt"));
  EXPECT_EQ(test::runCli(run + (tmp / "b").string() + " --set tracking.max_jump_m=far", &out), 2);
  EXPECT_NE(out.find("--set tracking.max_jump_m=far: invalid value"), std::string::npos) << out;
}

TEST(RunCli, FastIsThePipelinedSmallInputScheduleAndNeedsAKalmanMode) {
  TKGSLAM_REQUIRE_SHARED();
  test::TempDir tmp;
  const std::string run = "run --deterministic -q --max-frames 20 -c " +
                          (test::sourceDir() / "configs" / "tum_fr1.yaml").string() + " -d " + test::fr1xyz().string();
  std::string out;
  ASSERT_EQ(test::runCli(run + " --mode TKG --fast -o " + (tmp / "fast").string(), &out), 0) << out;
  ASSERT_EQ(test::runCli(run + " --mode TKG --detector-size 320 --detector-latency 1 --lookahead --opencv-threads 1 -o " +
                             (tmp / "flags").string(),
                         &out),
            0)
      << out;
  const std::string trajectory = test::readFile(tmp / "fast" / "trajectory.txt");
  EXPECT_GT(trajectory.size(), 1000u);
  EXPECT_EQ(test::readFile(tmp / "flags" / "trajectory.txt"), trajectory);
  const std::string used = test::readFile(tmp / "fast" / "config_used.yaml");
  for (const char* line : {"  detect_every: 1\n", "  detector_tiles: 1\n", "  detector_latency: 1\n",
                           "  lookahead: true\n", "  input_size: 320\n", "  opencv_threads: 1\n"}) {
    EXPECT_NE(used.find(line), std::string::npos) << line << used;
  }
  // Every frame was detected: 20 detector runs.
  EXPECT_NE(test::readFile(tmp / "fast" / "timing.json").find("\"detector\": {\"count\": 20,"), std::string::npos);
  // Options given explicitly win; the latency follows them (one run per detect_every x tiles frames).
  ASSERT_EQ(test::runCli(run + " --mode TK --fast --detect-every 2 --detector-tiles 4 --detector-size 640 -o " +
                             (tmp / "tiled").string(),
                         &out),
            0)
      << out;
  const std::string tiled = test::readFile(tmp / "tiled" / "config_used.yaml");
  for (const char* line : {"  detect_every: 2\n", "  detector_tiles: 4\n", "  detector_latency: 8\n", "  input_size: 640\n"}) {
    EXPECT_NE(tiled.find(line), std::string::npos) << line << tiled;
  }

  for (const char* mode : {"orb", "T", "TG"}) {
    EXPECT_EQ(test::runCli(run + " --fast --mode " + mode + " -o " + (tmp / mode).string(), &out), 2);
    EXPECT_NE(out.find(std::string("--fast holds frames for the Kalman box tracker: it needs --mode TK or TKG, not ") + mode),
              std::string::npos) << out;
  }
}

// With every frame detected, `run` lets the detector work on the next frame while this one is tracked
// (lookahead, latency 1): the same boxes, so the same trajectory as waiting for each detection.
TEST(RunCli, PipelineRunsTheDetectorOneFrameAheadWithTheSameTrajectory) {
  TKGSLAM_REQUIRE_SHARED();
  test::TempDir tmp;
  const std::string base = "run --deterministic -c " + (test::sourceDir() / "configs" / "tum_fr1.yaml").string() +
                           " -d " + test::fr1xyz().string();
  const std::string run = base + " --max-frames 40";
  std::string out;
  ASSERT_EQ(test::runCli(run + " --mode TKG -o " + (tmp / "on").string(), &out), 0) << out;
  EXPECT_NE(out.find("(deterministic, dynamic mode TKG, detector one frame ahead)"), std::string::npos) << out;
  ASSERT_EQ(test::runCli(run + " -q --mode TKG --pipeline off -o " + (tmp / "off").string(), &out), 0) << out;
  const std::string trajectory = test::readFile(tmp / "on" / "trajectory.txt");
  EXPECT_GT(trajectory.size(), 2000u);
  EXPECT_EQ(test::readFile(tmp / "off" / "trajectory.txt"), trajectory);
  // Not trivially the same: the person behind the desk is boxed.
  const std::string boxes = test::readFile(tmp / "on" / "dynamic.jsonl");
  EXPECT_NE(boxes.find("\"predicted\": false"), std::string::npos);
  EXPECT_EQ(test::readFile(tmp / "off" / "dynamic.jsonl"), boxes);
  // config_used.yaml says what ran, so it repeats the run.
  const std::string on = test::readFile(tmp / "on" / "config_used.yaml");
  EXPECT_NE(on.find("  detector_latency: 1\n"), std::string::npos) << on;
  EXPECT_NE(on.find("  lookahead: true\n"), std::string::npos) << on;
  EXPECT_NE(test::readFile(tmp / "on" / "timing.json").find("\"detector\": {\"count\": 40,"), std::string::npos);
  // The tracking thread's stages are disjoint parts of its time per frame: the wait for the detector
  // thread is detector_wait, not ORB extraction (it was both, which put ORB at 35 ms of a 39 ms frame).
  // The wait at the end of the run, for the last detection, is in no frame's total.
  const YAML::Node timing = YAML::LoadFile((tmp / "on" / "timing.json").string());
  const auto sum = [&](const char* stage) {
    return timing[stage]["mean_ms"].as<double>() * timing[stage]["count"].as<double>();
  };
  EXPECT_LE(sum("orb_extraction") + sum("tracking") + sum("detector_wait"),
            sum("total") + timing["detector_wait"]["max_ms"].as<double>() + 1.0)
      << test::readFile(tmp / "on" / "timing.json");
  const std::string off = test::readFile(tmp / "off" / "config_used.yaml");
  EXPECT_NE(off.find("  detector_latency: 0\n"), std::string::npos) << off;
  EXPECT_NE(off.find("  lookahead: false\n"), std::string::npos) << off;

  // Not pipelined: an explicit --detector-latency, a mode without the Kalman tracker (lookahead needs it;
  // a latency alone would make the detection late), flow forced on, sparse detection.
  for (const std::string flags : {"--mode TKG --detector-latency 0", "--mode TKG --set dynamic.detector_latency=0",
                                  "--mode T", "--mode TG", "--mode TKG --box-flow on", "--mode TKG --detect-every 2"}) {
    ASSERT_EQ(test::runCli(base + " -q --max-frames 3 " + flags + " -o " + (tmp / "x").string(), &out), 0) << out;
    EXPECT_EQ(out.find("one frame ahead"), std::string::npos) << flags << ": " << out;
    EXPECT_NE(test::readFile(tmp / "x" / "config_used.yaml").find("  lookahead: false\n"), std::string::npos) << flags;
  }
}

// A second run into the same folder must not leave the first run's files beside its own: an orb run
// after a TKG run would otherwise have the TKG run's dynamic.jsonl, and its report that run's boxes.
TEST(RunCli, ARunIntoAnEarlierRunsFolderReplacesAllItsOutputs) {
  TKGSLAM_REQUIRE_SHARED();
  test::TempDir tmp;
  const std::string run = "run --deterministic -q --max-frames 5 -c " +
                          (test::sourceDir() / "configs" / "tum_fr1.yaml").string() + " -d " + test::fr1xyz().string() +
                          " -o " + (tmp / "out").string();
  std::string out;
  ASSERT_EQ(test::runCli(run + " --mode TKG --report", &out), 0) << out;
  ASSERT_TRUE(std::filesystem::exists(tmp / "out" / "dynamic.jsonl"));
  test::writeText(tmp / "out" / "notes.txt", "mine");
  ASSERT_EQ(test::runCli(run + " --mode orb", &out), 0) << out;
  EXPECT_NE(out.find("replacing the outputs of an earlier run in"), std::string::npos) << out;
  EXPECT_FALSE(std::filesystem::exists(tmp / "out" / "dynamic.jsonl"));
  EXPECT_FALSE(std::filesystem::exists(tmp / "out" / "report.html"));
  EXPECT_TRUE(std::filesystem::exists(tmp / "out" / "trajectory.txt"));
  EXPECT_EQ(test::readFile(tmp / "out" / "notes.txt"), "mine") << "only run's own files are replaced";
  ASSERT_EQ(test::runCli("report " + (tmp / "out").string(), &out), 0) << out;
  EXPECT_EQ(test::readFile(tmp / "out" / "report.html").find("Dynamic objects"), std::string::npos);
}

// Into a file or pipe (`| tee run.log`) the summary on stdout and the progress on stderr come out
// in the order they happen: the run's header first, its result after the last progress line.
TEST(RunCli, TheSummaryAndTheProgressKeepTheirOrderInOneLog) {
  TKGSLAM_REQUIRE_SHARED();
  test::TempDir tmp;
  std::string out;
  ASSERT_EQ(test::runCli("run --deterministic --max-frames 50 -c " + (test::sourceDir() / "configs" / "tum_fr1.yaml").string() +
                             " -d " + test::fr1xyz().string() + " -o " + (tmp / "out").string(),
                         &out),
            0)
      << out;
  const auto header = out.find("tkgslam run: 50 frames"), progress = out.find("frame   50/50"),
             result = out.find("frames 50, tracked");
  ASSERT_NE(header, std::string::npos) << out;
  ASSERT_NE(progress, std::string::npos) << out;
  ASSERT_NE(result, std::string::npos) << out;
  EXPECT_LT(header, progress) << out;
  EXPECT_LT(progress, result) << out;
}

// A config copied away from the repository no longer finds the model by its relative path;
// --model gives it (an installed tkgslam has no ../shared beside its configs).
TEST(RunCli, ModelOverridesTheConfigsModel) {
  TKGSLAM_REQUIRE_SHARED();
  test::TempDir tmp;
  const auto config = tmp / "a" / "b" / "fr1.yaml";
  std::filesystem::create_directories(config.parent_path());
  std::filesystem::copy_file(test::sourceDir() / "configs" / "tum_fr1.yaml", config);
  const std::string run = "run --deterministic -q --mode TKG --max-frames 3 -c " + config.string() + " -d " +
                          test::fr1xyz().string() + " -o " + (tmp / "out").string();
  std::string out;
  EXPECT_EQ(test::runCli(run, &out), 2) << out;
  EXPECT_NE(out.find("detector: model file"), std::string::npos) << out;
  const std::string model = (test::sharedDir() / "models" / "yolov5n-coco-640.onnx").string();
  ASSERT_EQ(test::runCli(run + " --model " + model, &out), 0) << out;
  EXPECT_NE(test::readFile(tmp / "out" / "config_used.yaml")
                .find("model: " + std::filesystem::absolute(model).lexically_normal().string()),
            std::string::npos)
      << test::readFile(tmp / "out" / "config_used.yaml");
}

// A ground truth that does not fit the sequence (here in nanoseconds) costs the ATE, not the run:
// exit 0 with a warning, and a report without the accuracy plots.
TEST(RunCli, AGroundTruthThatDoesNotFitIsAWarning) {
  TKGSLAM_REQUIRE_SHARED();
  test::TempDir tmp;
  const auto seq = tmp / "seq";
  std::filesystem::create_directories(seq);
  for (const char* f : {"rgb", "depth"}) std::filesystem::create_directory_symlink(test::fr1xyz() / f, seq / f);
  for (const char* f : {"rgb.txt", "depth.txt"}) std::filesystem::copy_file(test::fr1xyz() / f, seq / f);
  std::ifstream in(test::fr1xyz() / "groundtruth.txt");
  std::string line, gt;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    const auto dot = line.find('.');
    gt += line.substr(0, dot) + line.substr(dot + 1, 4) + "00000" + line.substr(line.find(' ')) + "\n";  // ns
  }
  test::writeText(seq / "groundtruth.txt", gt);
  std::string out;
  ASSERT_EQ(test::runCli("run --deterministic --max-frames 5 --report -c " +
                             (test::sourceDir() / "configs" / "tum_fr1.yaml").string() + " -d " + seq.string() +
                             " -o " + (tmp / "out").string(),
                         &out),
            0)
      << out;
  EXPECT_NE(out.find("ATE not computed against"), std::string::npos) << out;
  EXPECT_NE(out.find("times the estimate's - nanoseconds?"), std::string::npos) << out;
  EXPECT_NE(test::readFile(tmp / "out" / "report.html").find("Ground truth not used: "), std::string::npos);
}

TEST(RunCli, ASavedMapPutsTheNextRunInItsWorldFrame) {
  TKGSLAM_REQUIRE_SHARED();
  test::TempDir tmp;
  const std::string run = "run --deterministic -q --mode orb -c " +
                          (test::sourceDir() / "configs" / "tum_fr1.yaml").string() + " -d " + test::fr1xyz().string();
  const std::string map = (tmp / "first.tkgmap").string();
  std::string out;
  ASSERT_EQ(test::runCli(run + " --max-frames 150 --save-map " + map + " -o " + (tmp / "first").string(), &out), 0)
      << out;
  EXPECT_NE(out.find("map saved: " + map), std::string::npos) << out;
  // Frames 150-299: in the saved map, and on their own.
  ASSERT_EQ(test::runCli(run + " --start-frame 150 --max-frames 150 --load-map " + map + " -o " +
                             (tmp / "second").string(),
                         &out),
            0)
      << out;
  EXPECT_NE(out.find("relocalising in it"), std::string::npos) << out;
  ASSERT_EQ(test::runCli(run + " --start-frame 150 --max-frames 150 -o " + (tmp / "alone").string(), &out), 0) << out;
  ASSERT_EQ(test::runCli(run + " --start-frame 150 --max-frames 150 --load-map " + map + " --localize -o " +
                             (tmp / "localized").string(),
                         &out),
            0)
      << out;
  EXPECT_NE(out.find("localisation only: the map is not changed"), std::string::npos) << out;
  EXPECT_NE(test::readFile(tmp / "localized" / "run.json").find("\"localization_only\": true"), std::string::npos);
  EXPECT_NE(test::readFile(tmp / "second" / "run.json").find("\"start_frame\": 150, \"map_loaded\": \"" + map + "\""),
            std::string::npos);

  // Both halves as one trajectory, aligned once: as good as one run over the 300 frames (0.0114 m)
  // when the second half is in the first's world frame; not when it starts a world of its own.
  const auto gt = io::readTumTrajectory((test::fr1xyz() / "groundtruth.txt").string());
  const auto first = io::readTumTrajectory((tmp / "first" / "trajectory.txt").string());
  const auto joined_ate = [&](const std::string& second) {
    auto joined = first;
    for (const auto& e : io::readTumTrajectory((tmp / second / "trajectory.txt").string())) joined.push_back(e);
    EXPECT_GE(joined.size(), 295u);
    return eval::computeAte(gt, joined).stats.rmse;
  };
  EXPECT_LT(joined_ate("second"), 0.014);     // measured 0.0110
  EXPECT_LT(joined_ate("localized"), 0.014);  // measured 0.0118
  EXPECT_GT(joined_ate("alone"), 0.020);      // measured 0.0241
  // keyframes.txt lists this run's keyframes: the loaded ones are in the map, not in its trajectory.
  const auto kfs = io::readTumTrajectory((tmp / "second" / "keyframes.txt").string());
  ASSERT_FALSE(kfs.empty());
  EXPECT_GE(kfs.front().timestamp, first.back().timestamp);
  // Localisation only: no keyframes of its own.
  EXPECT_TRUE(io::readTumTrajectory((tmp / "localized" / "keyframes.txt").string()).empty());

  // A map from another camera, a file that is no map, a folder that is not there: refused before the run.
  EXPECT_EQ(test::runCli("run -q -c " + (test::sourceDir() / "configs" / "tum_fr2.yaml").string() + " -d " +
                             test::fr1xyz().string() + " --load-map " + map + " -o " + (tmp / "x").string(),
                         &out),
            2);
  EXPECT_NE(out.find("the map was built with another camera"), std::string::npos) << out;
  EXPECT_EQ(test::runCli(run + " --load-map " + (tmp / "first" / "run.json").string() + " -o " + (tmp / "x").string(),
                         &out),
            2);
  EXPECT_NE(out.find("not a valid map file"), std::string::npos) << out;
  EXPECT_EQ(test::runCli(run + " --save-map " + (tmp / "nowhere" / "m.tkgmap").string() + " -o " + (tmp / "x").string(),
                         &out),
            2);
  EXPECT_NE(out.find("does not exist"), std::string::npos) << out;
  // ... nor a file that could not be written at the end of the run.
  EXPECT_EQ(test::runCli(run + " --save-map " + tmp.path().string() + " -o " + (tmp / "x").string(), &out), 2);
  EXPECT_NE(out.find("is a folder, not a file"), std::string::npos) << out;
  EXPECT_EQ(test::runCli(run + " --save-map /proc/m.tkgmap -o " + (tmp / "x").string(), &out), 2);
  EXPECT_NE(out.find("--save-map '/proc/m.tkgmap': cannot write there"), std::string::npos) << out;
  EXPECT_EQ(test::runCli(run + " --debug-dynamic /proc/d.jsonl -o " + (tmp / "x").string(), &out), 2);
  EXPECT_NE(out.find("--debug-dynamic '/proc/d.jsonl': cannot write there"), std::string::npos) << out;
  // Localising in a map of another place: the outputs are written, but the run is a failure.
  // (Mirrored frames: ORB descriptors are not mirror-invariant, so nothing matches the map.)
  const auto mirrored = tmp / "mirrored";
  const auto mirror = [](int) { return test::FrameFault::Mirrored; };
  test::writeFaultySequence(mirrored, 8, [](int) { return false; }, mirror, mirror);
  EXPECT_EQ(test::runCli("run --deterministic -q --mode orb -c " +
                             (test::sourceDir() / "configs" / "tum_fr1.yaml").string() + " -d " + mirrored.string() +
                             " --localize --load-map " + map + " -o " + (tmp / "nowhere_found").string(),
                         &out),
            2);
  EXPECT_NE(out.find("the camera was not found in the map '" + map + "' on any of the 8 frames"), std::string::npos)
      << out;
  EXPECT_TRUE(std::filesystem::exists(tmp / "nowhere_found" / "frame_log.txt"));

  EXPECT_EQ(test::runCli(run + " --localize -o " + (tmp / "x").string(), &out), 2);
  EXPECT_NE(out.find("--localize tracks in a saved map: give it with --load-map"), std::string::npos) << out;
  EXPECT_EQ(test::runCli(run + " --localize --load-map " + map + " --save-map " + (tmp / "again.tkgmap").string() +
                             " -o " + (tmp / "x").string(),
                         &out),
            2);
  EXPECT_NE(out.find("nothing new for --save-map to save"), std::string::npos) << out;
  EXPECT_EQ(test::runCli(run + " --start-frame 792 -o " + (tmp / "x").string(), &out), 2);
  EXPECT_NE(out.find("--start-frame 792: the sequence has 792 frames"), std::string::npos) << out;
  EXPECT_FALSE(std::filesystem::exists(tmp / "x"));
}

// ORB-SLAM2 users have association files: the same pairs from one give the same run.
TEST(RunCli, AFullDiskIsAnErrorAndLeavesNoPartOfAFile) {
  TKGSLAM_REQUIRE_SHARED();
  test::TempDir tmp;
  const auto out_dir = tmp / "out";
  // A file-size limit stands in for a full disk. dash's ulimit -f counts 512-byte blocks (bash's
  // 1024): the 30-frame map's PLY (~40 KB) is over either, its trajectory (~3 KB) under both.
  std::string out;
  const std::string run = " run --deterministic -q --max-frames 30 -c " +
                          (test::sourceDir() / "configs" / "tum_fr1.yaml").string() + " -d " + test::fr1xyz().string();
  EXPECT_EQ(test::runCommand("ulimit -f 40; " + std::string(TKGSLAM_CLI) + run + " -o " + out_dir.string(), &out), 2);
  EXPECT_NE(out.find("cannot write PLY file '" + (out_dir / "map.ply").string() + "': File too large"),
            std::string::npos)
      << out;
  EXPECT_FALSE(std::filesystem::exists(out_dir / "map.ply"));
  EXPECT_FALSE(std::filesystem::exists(out_dir / "map.ply.part"));
  EXPECT_EQ(io::readTumTrajectory((out_dir / "trajectory.txt").string()).size(), 30u);
}

TEST(RunCli, AnAssociationFileGivesTheSameRunAsTheLists) {
  TKGSLAM_REQUIRE_SHARED();
  test::TempDir tmp;
  const auto dir = test::fr1xyz();
  const io::TumDataset lists(dir.string());
  std::string text;  // associate.py's output: rgb first, names relative to the sequence folder
  for (int i = 0; i < 40; ++i) {
    const auto& e = lists.entry(i);
    text += fmt::format("{:.6f} {} {:.6f} {}\n", e.rgb_timestamp,
                        std::filesystem::path(e.rgb_path).lexically_relative(dir).string(), e.depth_timestamp,
                        std::filesystem::path(e.depth_path).lexically_relative(dir).string());
  }
  test::writeText(tmp / "associations.txt", text);
  const std::string run = "run --deterministic -q --mode orb --max-frames 30 -c " +
                          (test::sourceDir() / "configs" / "tum_fr1.yaml").string() + " -d " + dir.string();
  std::string out;
  ASSERT_EQ(test::runCli(run + " -o " + (tmp / "lists").string(), &out), 0) << out;
  ASSERT_EQ(test::runCli(run + " --associations " + (tmp / "associations.txt").string() + " -o " +
                             (tmp / "pairs").string(),
                         &out),
            0)
      << out;
  const std::string traj = test::readFile(tmp / "pairs" / "trajectory.txt");
  EXPECT_EQ(std::count(traj.begin(), traj.end(), '\n'), 31);  // a header line, 30 poses
  EXPECT_EQ(traj, test::readFile(tmp / "lists" / "trajectory.txt"));
  EXPECT_NE(test::readFile(tmp / "pairs" / "run.json").find("\"associations\": \"" + (tmp / "associations.txt").string()),
            std::string::npos);
  EXPECT_NE(test::readFile(tmp / "lists" / "run.json").find("\"associations\": null"), std::string::npos);
  EXPECT_EQ(test::runCli(run + " --associations " + (tmp / "none.txt").string() + " -o " + (tmp / "x").string(), &out),
            2);
  EXPECT_NE(out.find("none.txt' does not exist"), std::string::npos) << out;
}

TEST(RunCli, RunJsonIsValidJsonWhateverThePathsHold) {
  TKGSLAM_REQUIRE_SHARED();
  if (std::system("python3 -c 'import json' > /dev/null 2>&1") != 0) GTEST_SKIP() << "python3 not found";
  test::TempDir tmp;
  // A quote and a backslash in the dataset's and the map's paths.
  const auto data = tmp / "we\"ird\\seq";
  std::filesystem::create_directory_symlink(test::fr1xyz(), data);
  const auto map = tmp / "m\"ap.tkgmap";
  std::string out;
  ASSERT_EQ(test::runCli("run -q --deterministic --max-frames 3 -c " +
                             (test::sourceDir() / "configs" / "tum_fr1.yaml").string() + " -d '" + data.string() +
                             "' --save-map '" + map.string() + "' -o " + (tmp / "out").string(),
                         &out),
            0)
      << out;
  const std::string check = "python3 -c 'import json, sys; r = json.load(open(sys.argv[1])); "
                            "sys.exit(0 if r[\"dataset\"] == sys.argv[2] and r[\"map_saved\"] == sys.argv[3] "
                            "and r[\"map_loaded\"] is None and r[\"tkgslam_version\"] == sys.argv[4] else 1)' " +
                            (tmp / "out" / "run.json").string() + " '" + data.string() + "' '" + map.string() + "' " +
                            TKGSLAM_VERSION;
  EXPECT_EQ(std::system(check.c_str()), 0) << test::readFile(tmp / "out" / "run.json");
}

}  // namespace
}  // namespace tkgslam
