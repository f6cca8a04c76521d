// tkgslam run's outputs as a user relies on them.
#include <filesystem>

#include <gtest/gtest.h>

#include "TestSupport.h"

namespace tkgslam {
namespace {

TEST(RunCli, ConfigUsedHasTheCommandLinesOptionsAndRepeatsTheRun) {
  TKGSLAM_REQUIRE_SHARED();
  test::TempDir tmp;
  const std::string data = " -d " + test::fr1xyz().string() + " --max-frames 10 -q -o ";
  std::string out;
  ASSERT_EQ(test::runCli("run --deterministic --mode TKG --detect-every 2 --object-mask on -c " +
                             (test::sourceDir() / "configs" / "tum_fr1.yaml").string() + data + (tmp / "a").string(),
                         &out),
            0)
      << out;
  const std::string used = test::readFile(tmp / "a" / "config_used.yaml");
  EXPECT_NE(used.find("  mode: TKG\n"), std::string::npos) << used;
  EXPECT_NE(used.find("  detect_every: 2\n"), std::string::npos) << used;
  EXPECT_NE(used.find("  object_mask: true\n"), std::string::npos) << used;
  EXPECT_NE(used.find("  deterministic: true\n"), std::string::npos) << used;
  // The model path is absolute: the file lies in another folder than the config it came from.
  EXPECT_NE(used.find("  model: /"), std::string::npos) << used;

  // The same run from config_used.yaml alone, without the options: the same trajectory.
  ASSERT_EQ(test::runCli("run -c " + (tmp / "a" / "config_used.yaml").string() + data + (tmp / "b").string(), &out), 0)
      << out;
  const std::string trajectory = test::readFile(tmp / "a" / "trajectory.txt");
  EXPECT_GT(trajectory.size(), 500u);
  EXPECT_EQ(test::readFile(tmp / "b" / "trajectory.txt"), trajectory);
  // Below its first line (the file it came from), the same configuration.
  const std::string again = test::readFile(tmp / "b" / "config_used.yaml");
  EXPECT_EQ(again.substr(again.find('\n')), used.substr(used.find('\n')));
}

}  // namespace
}  // namespace tkgslam
