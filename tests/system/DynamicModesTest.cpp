// Dynamic handling must do no harm on a static scene: on the real fr1_xyz (one seated person in
// the background), TKG mode stays within 10 % of the ORB-SLAM2-style baseline's ATE.
#include <regex>

#include <gtest/gtest.h>

#include "TestSupport.h"
#include "tkgslam/eval/Ate.h"
#include "tkgslam/io/TrajectoryFile.h"

namespace tkgslam {
namespace {

double ateOf(const std::filesystem::path& traj) {
  return eval::computeAte(io::readTumTrajectory((test::fr1xyz() / "groundtruth.txt").string()),
                          io::readTumTrajectory(traj.string()))
      .stats.rmse;
}

TEST(DynamicModes, TkgDoesNoHarmOnTheStaticSequence) {
  TKGSLAM_REQUIRE_SHARED();
  test::TempDir tmp;
  const std::string common = "run --deterministic -q -c " + (test::sourceDir() / "configs/tum_fr1.yaml").string() +
                             " -d " + test::fr1xyz().string();
  std::string out;
  ASSERT_EQ(test::runCli(common + " --mode orb -o " + (tmp / "orb").string(), &out), 0) << out;
  ASSERT_EQ(test::runCli(common + " --mode TKG --debug-dynamic " + (tmp / "dyn.jsonl").string() + " -o " +
                             (tmp / "tkg").string(),
                         &out),
            0)
      << out;
  const double ate_orb = ateOf(tmp / "orb" / "trajectory.txt");
  const double ate_tkg = ateOf(tmp / "tkg" / "trajectory.txt");
  RecordProperty("ate_orb", std::to_string(ate_orb));
  RecordProperty("ate_tkg", std::to_string(ate_tkg));
  EXPECT_LE(ate_tkg, 1.1 * ate_orb) << "orb " << ate_orb << " TKG " << ate_tkg;
  EXPECT_EQ(io::readTumTrajectory((tmp / "tkg" / "trajectory.txt").string()).size(),
            io::readTumTrajectory((tmp / "orb" / "trajectory.txt").string()).size());
  // The seated person was detected and its keypoints dropped; timings have the dynamic columns.
  EXPECT_NE(out.find("keypoints dropped per frame"), std::string::npos) << out;
  std::ifstream dyn(tmp / "dyn.jsonl");
  std::string line;
  int lines = 0, with_person = 0;
  while (std::getline(dyn, line)) {
    ++lines;
    with_person += line.find("\"class\": 0") != std::string::npos;
  }
  EXPECT_GE(lines, 790);
  EXPECT_GT(with_person, 100);
  const std::string t = test::readFile(tmp / "tkg" / "timing.json");
  EXPECT_NE(t.find("\"detector\""), std::string::npos);
  EXPECT_NE(t.find("\"box_tracker\""), std::string::npos);
}

TEST(DynamicModes, UnknownModeIsAClearError) {
  std::string out;
  EXPECT_EQ(test::runCli("run --mode XYZ -c " + (test::sourceDir() / "configs/tum_fr1.yaml").string() +
                             " -d /tmp -o /tmp/x",
                         &out),
            2);
  EXPECT_NE(out.find("unknown dynamic mode 'XYZ'"), std::string::npos) << out;
}

TEST(DynamicModes, DetectorLatencyLongerThanItsPeriodIsAClearError) {
  TKGSLAM_REQUIRE_SHARED();
  test::TempDir tmp;
  std::string out;
  EXPECT_EQ(test::runCli("run --mode TKG --detect-every 2 --detector-latency 3 -c " +
                             (test::sourceDir() / "configs/tum_fr1.yaml").string() + " -d " + test::fr1xyz().string() +
                             " -o " + tmp.path().string(),
                         &out),
            2);
  EXPECT_NE(out.find("detector_latency must be in [0, detect_every = 2], got 3"), std::string::npos) << out;
}

TEST(DynamicModes, DetectorTilesWithoutLookaheadOrTooLateAreClearErrors) {
  TKGSLAM_REQUIRE_SHARED();
  test::TempDir tmp;
  const std::string run = "run --mode TKG --max-frames 5 -c " + (test::sourceDir() / "configs/tum_fr1.yaml").string() +
                          " -d " + test::fr1xyz().string() + " -o " + tmp.path().string();
  std::string out;
  EXPECT_EQ(test::runCli(run + " --detector-tiles 4", &out), 2);
  EXPECT_NE(out.find("--detector-tiles > 1 needs --lookahead"), std::string::npos) << out;
  EXPECT_EQ(test::runCli(run + " --detector-tiles 4 --lookahead --detector-latency 9", &out), 2);
  EXPECT_NE(out.find("detect_every x detector_tiles = 4], got 9"), std::string::npos) << out;
  EXPECT_EQ(test::runCli(run + " --detector-tiles 10 --lookahead", &out), 2);  // CLI range check
}

}  // namespace
}  // namespace tkgslam
