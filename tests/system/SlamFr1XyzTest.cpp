// End-to-end accuracy on the real TUM fr1_xyz sequence (deterministic mode), run twice: the
// trajectory must be identical bit for bit and accurate.
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "TestSupport.h"
#include "tkgslam/eval/Ate.h"
#include "tkgslam/io/TrajectoryFile.h"

namespace tkgslam {
namespace {

TEST(SlamFr1Xyz, AccurateCompleteAndDeterministic) {
  TKGSLAM_REQUIRE_SHARED();
  test::TempDir tmp;
  const std::string common = "run --deterministic -q -c " + (test::sourceDir() / "configs/tum_fr1.yaml").string() +
                             " -d " + test::fr1xyz().string() + " -o ";
  std::string out;
  ASSERT_EQ(test::runCli(common + (tmp / "a").string(), &out), 0) << out;
  ASSERT_EQ(test::runCli(common + (tmp / "b").string(), &out), 0) << out;

  const auto traj = test::readFile(tmp / "a" / "trajectory.txt");
  EXPECT_EQ(traj, test::readFile(tmp / "b" / "trajectory.txt")) << "deterministic mode gave different trajectories";

  const auto est = io::readTumTrajectory((tmp / "a" / "trajectory.txt").string());
  const auto gt = io::readTumTrajectory((test::fr1xyz() / "groundtruth.txt").string());
  const auto ate = eval::computeAte(gt, est);
  const double tracked = double(est.size()) / 798.0;  // rgb.txt lists 798 frames
  RecordProperty("ate_rmse_m", std::to_string(ate.stats.rmse));
  EXPECT_LE(ate.stats.rmse, 0.015);
  EXPECT_GE(tracked, 0.98);
  // The other outputs exist and are non-trivial.
  EXPECT_GT(io::readTumTrajectory((tmp / "a" / "keyframes.txt").string()).size(), 10u);
  EXPECT_NE(test::readFile(tmp / "a" / "map.ply").find("element vertex"), std::string::npos);
  EXPECT_NE(test::readFile(tmp / "a" / "timing.json").find("\"orb_and_tracking\""), std::string::npos);
  EXPECT_NE(out.find("ATE RMSE"), std::string::npos) << out;
}

TEST(SlamRunCli, BadInputIsAClearErrorNotACrash) {
  std::string out;
  EXPECT_EQ(test::runCli("run -c /nonexistent.yaml -d /tmp -o /tmp/x", &out), 2);
  EXPECT_NE(out.find("config file '/nonexistent.yaml' does not exist"), std::string::npos) << out;
  EXPECT_EQ(test::runCli("run -c " + (test::sourceDir() / "configs/tum_fr1.yaml").string() +
                             " -d /nonexistent/seq -o /tmp/x",
                         &out),
            2);
  EXPECT_NE(out.find("does not exist"), std::string::npos) << out;
  // A number out of range names the option and the rule, not CLI11's 0 to 1.8e308 written out.
  EXPECT_EQ(test::runCli("run -c " + (test::sourceDir() / "configs/tum_fr1.yaml").string() +
                             " -d /tmp -o /tmp/x --max-frames -3",
                         &out),
            2);
  EXPECT_NE(out.find("--max-frames: must be 0 or more, got -3"), std::string::npos) << out;
  EXPECT_LT(out.size(), 200u) << out;
  // An output folder that cannot be made is the user's input too (exit 2), not an internal error.
  test::TempDir tmp;
  test::writeText(tmp / "file", "x");
  test::writeText(tmp / "seq" / "rgb.txt", "1.0 rgb/1.png\n");
  test::writeText(tmp / "seq" / "depth.txt", "1.0 depth/1.png\n");
  test::writeText(tmp / "seq" / "rgb" / "1.png", "not an image");
  test::writeText(tmp / "seq" / "depth" / "1.png", "not an image");
  EXPECT_EQ(test::runCli("run -c " + (test::sourceDir() / "configs/tum_fr1.yaml").string() + " -d " +
                             (tmp / "seq").string() + " -o " + (tmp / "file").string(),
                         &out),
            2);
  EXPECT_NE(out.find("cannot create output folder"), std::string::npos) << out;
}

}  // namespace
}  // namespace tkgslam
