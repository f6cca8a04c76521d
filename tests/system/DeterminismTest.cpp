// Deterministic mode with the whole dynamic pipeline on (YOLO detector, Kalman box tracker,
// geometry check, local mapping): two runs must give byte-identical outputs.
#include <gtest/gtest.h>

#include "TestSupport.h"

namespace tkgslam {
namespace {

TEST(Determinism, TkgPipelineIsBitIdentical) {
  TKGSLAM_REQUIRE_SHARED();
  test::TempDir tmp;
  const std::string common = "run --deterministic -q --mode TKG --max-frames 150 -c " +
                             (test::sourceDir() / "configs/tum_fr1.yaml").string() + " -d " +
                             test::fr1xyz().string() + " -o ";
  std::string out;
  ASSERT_EQ(test::runCli(common + (tmp / "a").string(), &out), 0) << out;
  ASSERT_EQ(test::runCli(common + (tmp / "b").string(), &out), 0) << out;
  for (const char* file : {"trajectory.txt", "keyframes.txt", "map.ply", "dynamic.jsonl"}) {
    const auto a = test::readFile(tmp / "a" / file);
    EXPECT_FALSE(a.empty()) << file;
    EXPECT_EQ(a, test::readFile(tmp / "b" / file)) << file << " differs between two deterministic TKG runs";
  }
  // The detector really ran and its boxes removed keypoints (the seated person), so the
  // comparison covers the dynamic path and not just plain ORB tracking.
  const auto dyn = test::readFile(tmp / "a" / "dynamic.jsonl");
  EXPECT_NE(dyn.find("\"class\": 0"), std::string::npos);
  EXPECT_NE(dyn.find("\"dropped_points\": [["), std::string::npos);
}

}  // namespace
}  // namespace tkgslam
