// Faults in the middle of a run: unreadable and truncated images, frames without depth, a block of
// black frames (camera covered) and a jump (frames missing). The run must finish, say which
// frames it skipped or lost and why, recover after the bad block, and write its outputs.
// Ctrl-C (SIGINT) must also leave the outputs computed so far.
#include <fstream>

#include <fmt/format.h>

#include <opencv2/imgcodecs.hpp>

#include <gtest/gtest.h>

#include "TestSupport.h"
#include "tkgslam/eval/Ate.h"
#include "tkgslam/io/TrajectoryFile.h"
#include "tkgslam/io/TumDataset.h"

namespace tkgslam {
namespace {

namespace fs = std::filesystem;

TEST(FaultTolerance, BadFramesMidRunAreSkippedReportedAndTrackingRecovers) {
  TKGSLAM_REQUIRE_SHARED();
  test::TempDir tmp;
  const fs::path seq = tmp / "faulty";
  fs::create_directories(seq / "rgb");
  fs::create_directories(seq / "depth");
  io::TumDataset src(test::fr1xyz().string());
  std::string rgb_list, depth_list;
  std::vector<double> skipped_stamps;
  for (int i = 0; i < 200; ++i) {
    if (i >= 120 && i < 150) continue;  // the camera jumps: 30 frames missing
    const auto& e = src.entry(i);
    const fs::path rgb = seq / "rgb" / fs::path(e.rgb_path).filename();
    const fs::path depth = seq / "depth" / fs::path(e.depth_path).filename();
    if (i == 20 || i == 21) {
      test::writeText(rgb, "not an image");  // unreadable
      skipped_stamps.push_back(e.rgb_timestamp);
    } else if (i >= 70 && i < 85) {
      cv::imwrite(rgb.string(), cv::Mat::zeros(480, 640, CV_8UC3));  // camera covered
    } else {
      fs::copy_file(e.rgb_path, rgb);
    }
    if (i == 30) {
      test::writeText(depth, test::readFile(e.depth_path).substr(0, 200));  // truncated PNG
      skipped_stamps.push_back(e.rgb_timestamp);
    } else if (i >= 45 && i < 50) {
      cv::imwrite(depth.string(), cv::Mat::zeros(480, 640, CV_16UC1));  // no depth at all
    } else {
      fs::copy_file(e.depth_path, depth);
    }
    rgb_list += fmt::format("{:.6f} rgb/{}\n", e.rgb_timestamp, rgb.filename().string());
    depth_list += fmt::format("{:.6f} depth/{}\n", e.depth_timestamp, depth.filename().string());
  }
  test::writeText(seq / "rgb.txt", rgb_list);
  test::writeText(seq / "depth.txt", depth_list);
  fs::copy_file(test::fr1xyz() / "groundtruth.txt", seq / "groundtruth.txt");

  std::string out;
  const auto res = tmp / "out";
  ASSERT_EQ(test::runCli("run --deterministic -q -c " + (test::sourceDir() / "configs/tum_fr1.yaml").string() +
                             " -d " + seq.string() + " -o " + res.string(),
                         &out),
            0)
      << out;
  EXPECT_NE(out.find("skipped 3 (unreadable)"), std::string::npos) << out;
  const std::string log = test::readFile(res / "frame_log.txt");
  for (double t : skipped_stamps) EXPECT_NE(log.find(fmt::format("{:.6f} skipped", t)), std::string::npos) << log;
  EXPECT_NE(log.find("cannot read"), std::string::npos) << log;
  EXPECT_NE(log.find(" lost "), std::string::npos) << "the black frames are reported lost: " << log;

  const auto traj = io::readTumTrajectory((res / "trajectory.txt").string());
  // 170 listed frames, 3 unreadable, 15 black: most of the rest are tracked, including the end.
  EXPECT_GE(traj.size(), 140u);
  EXPECT_NEAR(traj.back().timestamp, src.entry(199).rgb_timestamp, 1e-4) << "no recovery after the bad block";
  const auto ate = eval::computeAte(io::readTumTrajectory((seq / "groundtruth.txt").string()), traj);
  EXPECT_LT(ate.stats.rmse, 0.05);
  for (const char* f : {"keyframes.txt", "map.ply", "timing.json", "run.json"}) EXPECT_TRUE(fs::exists(res / f)) << f;
}

TEST(FaultTolerance, InterruptWritesTheOutputsComputedSoFar) {
  TKGSLAM_REQUIRE_SHARED();
  test::TempDir tmp;
  const std::string cmd = "timeout --preserve-status -s INT 6 " + std::string(TKGSLAM_CLI) + " run -q -c " +
                          (test::sourceDir() / "configs/tum_fr1.yaml").string() + " -d " + test::fr1xyz().string() +
                          " -o " + (tmp / "out").string() + " > " + (tmp / "log.txt").string() + " 2>&1";
  const int status = std::system(cmd.c_str());
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 130) << test::readFile(tmp / "log.txt");
  EXPECT_NE(test::readFile(tmp / "log.txt").find("interrupted after"), std::string::npos) << test::readFile(tmp / "log.txt");
  const auto traj = io::readTumTrajectory((tmp / "out" / "trajectory.txt").string());
  EXPECT_GT(traj.size(), 20u);
  EXPECT_LT(traj.size(), 790u);
  EXPECT_TRUE(fs::exists(tmp / "out" / "map.ply"));
}

}  // namespace
}  // namespace tkgslam
