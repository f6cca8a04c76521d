// bench/tum_benchmark.sh: runs on real sequences, tables next to the paper's numbers, resumes, refuses
// bad input with exit code 2.
#include <filesystem>
#include <regex>

#include <gtest/gtest.h>

#include "TestSupport.h"

namespace tkgslam {
namespace {

namespace fs = std::filesystem;

/// Runs the script with `env` (VAR=value ...) and `args`; returns its exit code, output in `output`.
int runScript(const std::string& env, const std::string& args, std::string* output) {
  return test::runCommand("TKGSLAM_BIN=" + std::string(TKGSLAM_CLI) + " " + env + " bash " +
                              (test::sourceDir() / "bench" / "tum_benchmark.sh").string() + " " + args,
                          output);
}

/// The row of `sequence` in the table under the heading that starts with `heading` ("" if none).
std::string tableRow(const std::string& tables, const std::string& heading, const std::string& sequence) {
  const std::string table = test::markdownSection(tables, heading);
  const auto r = table.find("| " + sequence + " |");
  return r == std::string::npos ? "" : table.substr(r, table.find('\n', r) - r);
}

TEST(TumBenchmarkScript, RunsEachModeAndTabulatesItBesideThePapersNumbers) {
  TKGSLAM_REQUIRE_SHARED();
  test::TempDir tmp;
  // fr1_xyz twice: under its own name and under an fr3 dynamic sequence's name, whose row then has the
  // paper's published numbers (CONFIG keeps the fr1 camera for both).
  fs::create_directories(tmp / "tum");
  fs::create_directory_symlink(test::fr1xyz(), tmp / "tum" / "rgbd_dataset_freiburg1_xyz");
  fs::create_directory_symlink(test::fr1xyz(), tmp / "tum" / "rgbd_dataset_freiburg3_walking_xyz");
  const std::string env = "FRAMES=20 MODES='orb TKG' CONFIG=" + (test::sourceDir() / "configs" / "tum_fr1.yaml").string();
  const std::string args = "-o " + (tmp / "out").string() + " " + (tmp / "tum").string();
  std::string out;
  ASSERT_EQ(runScript(env, args, &out), 0) << out;
  EXPECT_NE(out.find("== [4/4] freiburg3_walking_xyz / TKG"), std::string::npos) << out;
  const std::string tables = test::readFile(tmp / "out" / "tables.md");

  // ATE of both modes on 20 frames of the static sequence: a few mm.
  const std::string ate = tableRow(tables, "ATE RMSE", "freiburg1_xyz");
  std::smatch m;
  ASSERT_TRUE(std::regex_search(ate, m, std::regex(R"(^\| freiburg1_xyz \| (0\.\d{4}) / 0\.\d{4} \| (0\.\d{4}) / 0\.\d{4} \| — \| — \| — \|$)")))
      << tables;
  EXPECT_LT(std::stod(m[1]), 0.02);
  EXPECT_LT(std::stod(m[2]), 0.02);
  // The paper's Table 1 (TKG-SLAM, CFP-SLAM, DynaSLAM on walking_xyz) and Table 2.
  EXPECT_NE(tableRow(tables, "ATE RMSE", "freiburg3_walking_xyz").find("| 0.0129 / 0.0067 | 0.0141 / 0.0072 | 0.0164 / 0.0086 |"),
            std::string::npos) << tables;
  EXPECT_NE(tableRow(tables, "RPE translation", "freiburg3_walking_xyz").find("| 0.0114 / 0.0064 |"), std::string::npos)
      << tables;
  // The ablation beside the paper's Table 3, for the walking sequences only.
  EXPECT_NE(tableRow(tables, "Ablation", "freiburg3_walking_xyz").find(" | 0.0129 / 0.0067 |"), std::string::npos) << tables;
  EXPECT_EQ(tableRow(tables, "Ablation", "freiburg1_xyz"), "") << tables;
  EXPECT_EQ(tableRow(tables, "Tracked frames", "freiburg1_xyz"), "| freiburg1_xyz | 100.0 | 100.0 |") << tables;
  // Time: orb is T by definition; TKG runs YOLO on every frame, so it costs more.
  const std::string time = tableRow(tables, "Mean time per frame", "freiburg1_xyz");
  ASSERT_TRUE(std::regex_search(time, m, std::regex(R"(\(1\.00 T\) \| [0-9.]+ \(([0-9.]+) T\) \|$)"))) << tables;
  EXPECT_GT(std::stod(m[1]), 1.0);

  // A second call keeps the finished runs.
  ASSERT_EQ(runScript(env, args, &out), 0) << out;
  EXPECT_NE(out.find("== [1/4] freiburg1_xyz / orb: done before"), std::string::npos) << out;
  EXPECT_EQ(test::readFile(tmp / "out" / "tables.md"), tables);
}

TEST(TumBenchmarkScript, RefusesWhatItCannotRunWithExitCode2) {
  TKGSLAM_REQUIRE_SHARED();
  test::TempDir tmp;
  const std::string o = "-o " + (tmp / "out").string() + " ";
  std::string out;
  fs::create_directories(tmp / "empty");
  EXPECT_EQ(runScript("", o + (tmp / "empty").string(), &out), 2);
  EXPECT_NE(out.find("no TUM sequence (a folder with rgb.txt) in"), std::string::npos) << out;

  // The camera config comes from "freiburgN" in the folder's name.
  fs::create_directory_symlink(test::fr1xyz(), tmp / "my_sequence");
  EXPECT_EQ(runScript("", o + (tmp / "my_sequence").string(), &out), 2);
  EXPECT_NE(out.find("no 'freiburg1/2/3' in the name to pick the camera config; set CONFIG=FILE"), std::string::npos)
      << out;

  EXPECT_EQ(runScript("MODES='orb TKGx'", o + (tmp / "my_sequence").string(), &out), 2);
  EXPECT_NE(out.find("unknown mode 'TKGx'"), std::string::npos) << out;
  EXPECT_FALSE(fs::exists(tmp / "out"));  // nothing written before the input is known to be good
}

}  // namespace
}  // namespace tkgslam
