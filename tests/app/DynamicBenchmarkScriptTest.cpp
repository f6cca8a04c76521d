// bench/dynamic_benchmark.sh: builds a composite, runs the modes, tabulates them; JOBS=2 gives the
// same accuracy tables as one run at a time; bad JOBS or modes are refused with exit code 2.
#include <filesystem>
#include <regex>

#include <gtest/gtest.h>

#include "TestSupport.h"

namespace tkgslam {
namespace {

namespace fs = std::filesystem;

/// Runs the script on `out` with `env` (VAR=value ...); returns its exit code, output in `output`.
int runScript(const std::string& env, const fs::path& out, std::string* output) {
  return test::runCommand("TKGSLAM_BIN=" + std::string(TKGSLAM_CLI) + " SEQ=" + test::fr1xyz().string() +
                              " PEOPLE=" + (test::sharedDir() / "datasets" / "people").string() + " " + env +
                              " bash " + (test::sourceDir() / "bench" / "dynamic_benchmark.sh").string() + " " +
                              out.string(),
                          output);
}

TEST(DynamicBenchmarkScript, TwoRunsAtATimeGiveTheSameAccuracyTables) {
  TKGSLAM_REQUIRE_SHARED();
  test::TempDir tmp;
  const std::string env = "FRAMES=30 MODES='orb TKG' ONLY='static low'";
  std::string out;
  ASSERT_EQ(runScript(env + " JOBS=2", tmp / "two", &out), 0) << out;
  ASSERT_TRUE(fs::exists(tmp / "two" / "seq_low" / "groundtruth.txt")) << out;
  const std::string two = test::readFile(tmp / "two" / "tables.md");

  // Both modes on both sequences, with an ATE of a few mm on 30 frames.
  const std::string ate = test::markdownSection(two, "ATE RMSE");
  for (const std::string seq : {"static", "low"}) {
    std::smatch m;
    ASSERT_TRUE(std::regex_search(
        ate, m, std::regex("\\| " + seq + R"( \| (0\.\d{4}) / 0\.\d{4} \|( — / — \|){3} (0\.\d{4}) / 0\.\d{4} \|)")))
        << two;
    EXPECT_LT(std::stod(m[1]), 0.03) << seq;
    EXPECT_LT(std::stod(m[3]), 0.03) << seq;
  }
  EXPECT_NE(two.find("these runs went 2 at a time"), std::string::npos) << two;

  // One at a time on the same composite (the runs are deterministic): the same accuracy tables.
  fs::create_directories(tmp / "one");
  fs::create_directory_symlink(tmp / "two" / "seq_low", tmp / "one" / "seq_low");
  ASSERT_EQ(runScript(env, tmp / "one", &out), 0) << out;
  const std::string one = test::readFile(tmp / "one" / "tables.md");
  for (const std::string heading : {"ATE RMSE", "RPE translation", "Tracked frames", "Dynamic keypoints"}) {
    EXPECT_FALSE(test::markdownSection(one, heading).empty()) << heading;
    EXPECT_EQ(test::markdownSection(one, heading), test::markdownSection(two, heading)) << heading;
  }
  EXPECT_EQ(one.find("at a time"), std::string::npos) << one;
}

TEST(DynamicBenchmarkScript, RefusesABadJobCountOrModeWithExitCode2) {
  TKGSLAM_REQUIRE_SHARED();
  test::TempDir tmp;
  std::string out;
  EXPECT_EQ(runScript("JOBS=0", tmp / "out", &out), 2) << out;
  EXPECT_NE(out.find("JOBS must be a positive whole number"), std::string::npos) << out;
  EXPECT_EQ(runScript("JOBS=two", tmp / "out", &out), 2) << out;
  EXPECT_EQ(runScript("MODES='orb TKGx'", tmp / "out", &out), 2) << out;
  EXPECT_NE(out.find("unknown mode 'TKGx'"), std::string::npos) << out;
  EXPECT_FALSE(fs::exists(tmp / "out" / "seq_low")) << "nothing is built before the input is checked";
}

TEST(DynamicBenchmarkScript, SetPassesConfigOverridesToEveryRunAndTheTablesSayWhich) {
  TKGSLAM_REQUIRE_SHARED();
  test::TempDir tmp;
  const std::string env = "FRAMES=10 MODES=orb ONLY=static ";
  std::string out;
  ASSERT_EQ(runScript(env + "SET='loop.min_inliers=33 camera.distortion=[0.26,-0.95,0,0,1.16]'", tmp / "set", &out), 0)
      << out;
  const std::string used = test::readFile(tmp / "set" / "runs" / "static" / "orb" / "config_used.yaml");
  EXPECT_NE(used.find("  min_inliers: 33\n"), std::string::npos) << used;
  EXPECT_NE(used.find("  distortion: [0.26, -0.95, 0, 0, 1.16]\n"), std::string::npos) << used;
  EXPECT_NE(test::readFile(tmp / "set" / "tables.md").find("loop.min_inliers=33"), std::string::npos);
  // A typo fails the run, and the script says why.
  EXPECT_EQ(runScript(env + "SET='loop.min_inlier=33'", tmp / "typo", &out), 1) << out;
  EXPECT_NE(out.find("unknown key 'loop.min_inlier'"), std::string::npos) << out;
}

}  // namespace
}  // namespace tkgslam
