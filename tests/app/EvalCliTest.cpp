#include <cmath>
#include <filesystem>
#include <sstream>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "TestSupport.h"

namespace tkgslam {
namespace {

TEST(EvalCli, ScoresReferenceTrajectoryAndWritesPlot) {
  TKGSLAM_REQUIRE_SHARED();
  const auto ref = test::sharedDir() / "datasets" / "reference_trajectories";
  test::TempDir tmp;
  std::string out;
  const int rc = test::runCli("eval " + (ref / "groundtruth_fr3_walk_xyz.txt").string() + " " +
                                  (ref / "dynaslam_fr3_walk_xyz" / "CameraTrajectory_0.txt").string() +
                                  " --plot " + (tmp / "plot.svg").string(),
                              &out);
  EXPECT_EQ(rc, 0) << out;
  EXPECT_NE(out.find("rmse 0.0163"), std::string::npos) << out;
  EXPECT_NE(out.find("rmse 0.0218"), std::string::npos) << out;
  EXPECT_GT(std::filesystem::file_size(tmp / "plot.svg"), 10000u);
}

TEST(EvalCli, PerPoseErrorsAddUpToTheReportedAte) {
  TKGSLAM_REQUIRE_SHARED();
  const auto ref = test::sharedDir() / "datasets" / "reference_trajectories";
  test::TempDir tmp;
  std::string out;
  ASSERT_EQ(test::runCli("eval " + (ref / "groundtruth_fr3_walk_xyz.txt").string() + " " +
                             (ref / "dynaslam_fr3_walk_xyz" / "CameraTrajectory_0.txt").string() + " --errors " +
                             (tmp / "errors.txt").string(),
                         &out),
            0)
      << out;
  std::istringstream in(test::readFile(tmp / "errors.txt"));
  std::string line;
  int rows = 0;
  double sum_sq = 0, last_t = 0;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream row(line);
    double t, e, g[3], a[3];
    ASSERT_TRUE(row >> t >> e >> g[0] >> g[1] >> g[2] >> a[0] >> a[1] >> a[2]) << line;
    EXPECT_GT(t, last_t);
    // The error column is the distance between the two positions on the line.
    EXPECT_NEAR(e, std::hypot(g[0] - a[0], g[1] - a[1], g[2] - a[2]), 2e-6) << line;
    sum_sq += e * e;
    last_t = t;
    ++rows;
  }
  EXPECT_NE(out.find(fmt::format("pairs {}", rows)), std::string::npos) << out;
  EXPECT_NEAR(std::sqrt(sum_sq / rows), 0.0163, 5e-5);  // the TUM script's ATE for this estimate
}

TEST(EvalCli, JsonAndTrackedRatio) {
  TKGSLAM_REQUIRE_SHARED();
  const auto ds = test::fr1xyz();
  std::string out;
  const int rc = test::runCli("eval --json --frames " + ds.string() + " " + (ds / "groundtruth.txt").string() + " " +
                                  (test::sharedDir() / "datasets/reference_trajectories/freiburg1_xyz-rgbdslam.txt").string(),
                              &out);
  EXPECT_EQ(rc, 0) << out;
  EXPECT_NE(out.find("\"ate_m\": {\"count\": "), std::string::npos) << out;
  EXPECT_NE(out.find("\"rmse\": 0.01347"), std::string::npos) << out;  // RGBD-SLAM: 0.0135
  EXPECT_NE(out.find("\"input_frames\": 798"), std::string::npos) << out;
}

// A run shorter than the RPE delta (e.g. --max-frames 20) still has an ATE worth reporting.
TEST(EvalCli, ATrajectoryShorterThanTheRpeDeltaGetsItsAteAndSaysWhyThereIsNoRpe) {
  test::TempDir tmp;
  std::string gt, est;
  for (int i = 0; i < 10; ++i) {
    gt += fmt::format("{:.2f} {:.3f} {:.3f} 0 0 0 0 1\n", 100 + 0.05 * i, 0.01 * i, 0.002 * i * i);
    est += fmt::format("{:.2f} {:.3f} {:.3f} 0.01 0 0 0 1\n", 100 + 0.05 * i, 0.01 * i, 0.002 * i * i + (i % 2) * 0.004);
  }
  test::writeText(tmp / "gt.txt", gt);
  test::writeText(tmp / "est.txt", est);
  const std::string files = (tmp / "gt.txt").string() + " " + (tmp / "est.txt").string();
  std::string out;
  EXPECT_EQ(test::runCli("eval " + files, &out), 0) << out;
  EXPECT_NE(out.find("ATE: pairs 10  rmse 0.0020"), std::string::npos) << out;
  EXPECT_NE(out.find("RPE (1 s): not computed - RPE: no pose pair 1 s apart"), std::string::npos) << out;
  EXPECT_NE(out.find("the estimate spans 0.45 s"), std::string::npos) << out;
  EXPECT_EQ(test::runCli("eval --json " + files, &out), 0) << out;
  EXPECT_NE(out.find("\"rpe_translation_m\": null"), std::string::npos) << out;
  EXPECT_NE(out.find("\"rmse\": 0.00199"), std::string::npos) << out;
  // With a delta the trajectory spans, RPE is there.
  EXPECT_EQ(test::runCli("eval --delta 0.1 " + files, &out), 0) << out;
  EXPECT_NE(out.find("RPE translation (0.1 s): pairs"), std::string::npos) << out;
  // Or a delta in frames (evaluate_rpe.py's --delta_unit f): 10 poses, the last one no pair's start.
  EXPECT_EQ(test::runCli("eval --delta 2 --delta-unit f " + files, &out), 0) << out;
  EXPECT_NE(out.find("RPE translation (2 f): pairs 7 "), std::string::npos) << out;
  EXPECT_EQ(test::runCli("eval --json --delta 2 --delta-unit f " + files, &out), 0) << out;
  EXPECT_NE(out.find("\"rpe_delta\": 2, \"rpe_delta_unit\": \"f\", \"rpe_delta_s\": null"), std::string::npos) << out;
  EXPECT_EQ(test::runCli("eval --delta 20 --delta-unit f " + files, &out), 0) << out;
  EXPECT_NE(out.find("no pose pair 20 f apart matches the ground truth (the estimate spans 9.00 f)"), std::string::npos)
      << out;
}

// The TUM scripts' --offset and --scale: an estimate whose clock is 1000 s ahead and whose positions
// are doubled scores as the original (the TUM scripts' output for it) once both are given back.
TEST(EvalCli, OffsetAndScaleUndoAShiftedClockAndAScaledTrajectory) {
  TKGSLAM_REQUIRE_SHARED();
  const auto ref = test::sharedDir() / "datasets" / "reference_trajectories";
  test::TempDir tmp;
  std::istringstream in(test::readFile(ref / "dynaslam_fr3_walk_xyz" / "CameraTrajectory_0.txt"));
  std::string line, moved;
  while (std::getline(in, line)) {
    std::istringstream row(line);
    double t, x, y, z, qx, qy, qz, qw;
    if (!(row >> t >> x >> y >> z >> qx >> qy >> qz >> qw)) continue;
    moved += fmt::format("{:.6f} {:.9f} {:.9f} {:.9f} {:.9f} {:.9f} {:.9f} {:.9f}\n", t + 1000, 2 * x, 2 * y, 2 * z, qx, qy,
                         qz, qw);
  }
  test::writeText(tmp / "moved.txt", moved);
  const std::string files = (ref / "groundtruth_fr3_walk_xyz.txt").string() + " " + (tmp / "moved.txt").string();
  std::string out;
  EXPECT_EQ(test::runCli("eval " + files, &out), 2) << out;  // no stamp of the ground truth's span
  EXPECT_NE(out.find("fewer than 2 timestamps of the estimate match the ground truth (|dt| < 0.02 s): the estimate "
                     "spans"),
            std::string::npos)
      << out;
  EXPECT_NE(out.find("which do not overlap (eval --offset shifts the estimate)"), std::string::npos) << out;
  ASSERT_EQ(test::runCli("eval --offset -1000 --scale 0.5 " + files, &out), 0) << out;
  // dynaslam_fr3_walk_xyz/ate.txt and rpe.txt:
  EXPECT_NE(out.find("rmse 0.0163  mean 0.0139  median 0.0122  std 0.0086  min 0.0016  max 0.0572 m"),
            std::string::npos)
      << out;
  EXPECT_NE(out.find("rmse 0.0218  mean 0.0184  median 0.0161  std 0.0116  min 0.0010  max 0.0863 m"),
            std::string::npos)
      << out;
  // Without the scale the doubled trajectory cannot be aligned (a rigid alignment has no scale).
  ASSERT_EQ(test::runCli("eval --offset -1000 " + files, &out), 0) << out;
  EXPECT_NE(out.find("ATE: pairs 757  rmse 0.3154"), std::string::npos) << out;
  ASSERT_EQ(test::runCli("eval --json --offset -1000 --scale 0.5 " + files, &out), 0) << out;
  EXPECT_NE(out.find("\"offset_s\": -1000.000000, \"scale\": 0.500000, \"max_difference_s\": 0.020000"),
            std::string::npos)
      << out;
}

// evaluate_ate.py's --max_difference: a tighter window pairs fewer poses.
TEST(EvalCli, MaxDifferenceIsTheAteAssociationWindow) {
  TKGSLAM_REQUIRE_SHARED();
  const std::string files = (test::fr1xyz() / "groundtruth.txt").string() + " " +
                            (test::sharedDir() / "datasets/reference_trajectories/freiburg1_xyz-rgbdslam.txt").string();
  std::string out;
  ASSERT_EQ(test::runCli("eval " + files, &out), 0) << out;
  EXPECT_NE(out.find("ATE: pairs 786  rmse 0.0135"), std::string::npos) << out;
  ASSERT_EQ(test::runCli("eval --max-difference 0.002 " + files, &out), 0) << out;
  EXPECT_NE(out.find("ATE: pairs 318  rmse 0.0129"), std::string::npos) << out;
  EXPECT_EQ(test::runCli("eval --max-difference 0.000001 " + files, &out), 2) << out;
  EXPECT_NE(out.find("(|dt| < 1e-06 s)"), std::string::npos) << out;
}

TEST(EvalCli, BadInputExitsWithTwoAndAMessage) {
  test::TempDir tmp;
  test::writeText(tmp / "bad.txt", "1 2 3\n");
  test::writeText(tmp / "ok.txt", "1 0 0 0 0 0 0 1\n2 0 0 0 0 0 0 1\n");
  std::string out;
  EXPECT_EQ(test::runCli("eval " + (tmp / "ok.txt").string() + " " + (tmp / "bad.txt").string(), &out), 2);
  EXPECT_NE(out.find("bad.txt:1"), std::string::npos) << out;
  EXPECT_EQ(test::runCli("eval /nonexistent.txt " + (tmp / "ok.txt").string(), &out), 2);
  EXPECT_NE(out.find("trajectory file '/nonexistent.txt' does not exist"), std::string::npos) << out;
  EXPECT_EQ(test::runCli("eval " + (tmp / "ok.txt").string() + " " + tmp.path().string(), &out), 2);
  EXPECT_NE(out.find("trajectory file '" + tmp.path().string() + "' is a folder, not a file"), std::string::npos)
      << out;
  EXPECT_EQ(test::runCli("eval", &out), 2);
  EXPECT_EQ(test::runCli("eval --delta 0 " + (tmp / "ok.txt").string() + " " + (tmp / "ok.txt").string(), &out), 2);
  EXPECT_NE(out.find("--delta: must be more than 0, got 0"), std::string::npos) << out;
  const std::string files = " " + (tmp / "ok.txt").string() + " " + (tmp / "ok.txt").string();
  EXPECT_EQ(test::runCli("eval --scale 0" + files, &out), 2);
  EXPECT_NE(out.find("--scale: must be more than 0, got 0"), std::string::npos) << out;
  EXPECT_EQ(test::runCli("eval --scale inf" + files, &out), 2);
  EXPECT_NE(out.find("--scale: must be finite, got inf"), std::string::npos) << out;
  EXPECT_EQ(test::runCli("eval --offset nan" + files, &out), 2);
  EXPECT_NE(out.find("--offset: 'nan' is not a number"), std::string::npos) << out;
  EXPECT_EQ(test::runCli("eval --max-difference -0.1" + files, &out), 2);
  EXPECT_NE(out.find("--max-difference: must be more than 0"), std::string::npos) << out;
  EXPECT_EQ(test::runCli("eval --delta-unit ms" + files, &out), 2);
  EXPECT_NE(out.find("--delta-unit: ms not in {s,f,m,rad,deg}"), std::string::npos) << out;
  // Outputs that cannot be written: a full disk is an error, not a plot cut short.
  if (std::filesystem::exists("/dev/full")) {
    EXPECT_EQ(test::runCli("eval --plot /dev/full" + files, &out), 2);
    EXPECT_NE(out.find("cannot write plot '/dev/full': No space left on device"), std::string::npos) << out;
    EXPECT_EQ(test::runCli("eval --errors /dev/full" + files, &out), 2);
    EXPECT_NE(out.find("cannot write error file '/dev/full': No space left on device"), std::string::npos) << out;
  }
}

}  // namespace
}  // namespace tkgslam
