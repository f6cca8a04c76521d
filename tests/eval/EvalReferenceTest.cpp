// The evaluator must reproduce the TUM benchmark scripts' own output (ate.txt from
// evaluate_ate.py, rpe.txt from evaluate_rpe.py --fixed_delta --delta 1) to the 4th decimal.
#include <fstream>
#include <map>
#include <sstream>

#include <gtest/gtest.h>

#include "TestSupport.h"
#include "tkgslam/eval/Ate.h"
#include "tkgslam/eval/Rpe.h"
#include "tkgslam/io/TrajectoryFile.h"

namespace tkgslam {
namespace {

// "KEY: value" lines -> map.
std::map<std::string, double> readReport(const std::filesystem::path& p) {
  std::map<std::string, double> out;
  std::ifstream in(p);
  std::string line;
  while (std::getline(in, line)) {
    const auto colon = line.find(':');
    if (colon == std::string::npos) continue;
    out[line.substr(0, colon)] = std::stod(line.substr(colon + 1));
  }
  return out;
}

struct Case {
  const char* estimate_dir;
  const char* ground_truth;
};

// Named in ctest's listing instead of gtest's byte dump of the struct.
void PrintTo(const Case& c, std::ostream* os) { *os << c.estimate_dir << " vs " << c.ground_truth; }

class EvalReference : public ::testing::TestWithParam<Case> {};

TEST_P(EvalReference, MatchesTumScriptsToFourDecimals) {
  TKGSLAM_REQUIRE_SHARED();
  const auto ref = test::sharedDir() / "datasets" / "reference_trajectories";
  const auto dir = ref / GetParam().estimate_dir;
  const auto gt = io::readTumTrajectory((ref / GetParam().ground_truth).string());
  const auto est = io::readTumTrajectory((dir / "CameraTrajectory_0.txt").string());

  const auto ate_ref = readReport(dir / "ate.txt");
  const auto rpe_ref = readReport(dir / "rpe.txt");
  ASSERT_TRUE(rpe_ref.count("Trans RMSE")) << "reference rpe.txt unreadable";
  const auto ate = eval::computeAte(gt, est);
  const auto rpe = eval::computeRpe(gt, est, 1.0);
  const double tol = 0.5e-4 + 1e-9;  // the reference values are printed with 4 decimals
  if (ate_ref.count("RMSE")) {  // one reference ate.txt is empty
    EXPECT_NEAR(ate.stats.rmse, ate_ref.at("RMSE"), tol);
    EXPECT_NEAR(ate.stats.mean, ate_ref.at("MEAN"), tol);
    EXPECT_NEAR(ate.stats.median, ate_ref.at("MEDIAN"), tol);
    EXPECT_NEAR(ate.stats.std, ate_ref.at("STD"), tol);
    EXPECT_NEAR(ate.stats.min, ate_ref.at("MIN"), tol);
    EXPECT_NEAR(ate.stats.max, ate_ref.at("MAX"), tol);
  }
  EXPECT_NEAR(rpe.translation.rmse, rpe_ref.at("Trans RMSE"), tol);
  EXPECT_NEAR(rpe.translation.mean, rpe_ref.at("Trans MEAN"), tol);
  EXPECT_NEAR(rpe.translation.median, rpe_ref.at("Trans MEDIAN"), tol);
  EXPECT_NEAR(rpe.translation.std, rpe_ref.at("Trans STD"), tol);
  EXPECT_NEAR(rpe.translation.max, rpe_ref.at("Trans MAX"), tol);
  EXPECT_NEAR(rpe.rotation_deg.rmse, rpe_ref.at("Rotation RMSE"), tol);
  EXPECT_NEAR(rpe.rotation_deg.mean, rpe_ref.at("Rotation MEAN"), tol);
  EXPECT_NEAR(rpe.rotation_deg.max, rpe_ref.at("Rotation MAX"), tol);
  // evaluate_rpe.py prints the rotational median in radians (a known quirk of the script).
  EXPECT_NEAR(rpe.rotation_deg.median * M_PI / 180.0, rpe_ref.at("Rotation MEDIAN"), tol);
}

INSTANTIATE_TEST_SUITE_P(
    DynaSlamFr3, EvalReference,
    ::testing::Values(Case{"dynaslam_fr3_sitting_static", "groundtruth_fr3_sit_static.txt"},
                      Case{"dynaslam_fr3_walk_halfsphere", "groundtruth_fr3_walk_half.txt"},
                      Case{"dynaslam_fr3_walk_rpy", "groundtruth_fr3_walk_rpy.txt"},
                      Case{"dynaslam_fr3_walk_static", "groundtruth_fr3_walk_static.txt"},
                      Case{"dynaslam_fr3_walk_xyz", "groundtruth_fr3_walk_xyz.txt"}),
    [](const auto& info) { return std::string(info.param.estimate_dir).substr(13); });

}  // namespace
}  // namespace tkgslam
