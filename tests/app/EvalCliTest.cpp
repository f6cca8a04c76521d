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

TEST(EvalCli, BadInputExitsWithTwoAndAMessage) {
  test::TempDir tmp;
  test::writeText(tmp / "bad.txt", "1 2 3\n");
  test::writeText(tmp / "ok.txt", "1 0 0 0 0 0 0 1\n2 0 0 0 0 0 0 1\n");
  std::string out;
  EXPECT_EQ(test::runCli("eval " + (tmp / "ok.txt").string() + " " + (tmp / "bad.txt").string(), &out), 2);
  EXPECT_NE(out.find("bad.txt:1"), std::string::npos) << out;
  EXPECT_EQ(test::runCli("eval /nonexistent.txt " + (tmp / "ok.txt").string(), &out), 2);
  EXPECT_NE(out.find("cannot open"), std::string::npos) << out;
  EXPECT_EQ(test::runCli("eval", &out), 2);
}

}  // namespace
}  // namespace tkgslam
