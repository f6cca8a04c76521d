// `cmake --install` gives a package other projects use: find_package(tkgslam) and the target
// tkgslam::tkgslam, with the headers and every dependency (yaml-cpp and Ceres are private to the
// static library, so the package must still bring them to the link). A small project is built
// against an install into a temporary prefix and must compute what the library computes here.
#include <cmath>
#include <filesystem>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "TestSupport.h"
#include "tkgslam/eval/Ate.h"
#include "tkgslam/io/ConfigFile.h"
#include "tkgslam/io/TrajectoryFile.h"

namespace tkgslam {
namespace {

constexpr const char* kConsumerCMake = R"(cmake_minimum_required(VERSION 3.18)
project(consumer CXX)
set(CMAKE_CXX_STANDARD 17)
find_package(tkgslam 0.1 REQUIRED)
add_executable(consumer main.cpp)
target_link_libraries(consumer PRIVATE tkgslam::tkgslam)
)";

constexpr const char* kConsumerMain = R"(#include <cstdio>
#include "tkgslam/eval/Ate.h"
#include "tkgslam/io/ConfigFile.h"
#include "tkgslam/io/TrajectoryFile.h"
int main(int argc, char** argv) {
  using namespace tkgslam;
  const auto ate = eval::computeAte(io::readTumTrajectory(argv[1]), io::readTumTrajectory(argv[2]));
  const SlamConfig config = io::loadConfig(argv[3]);
  std::printf("ate %.9f fx %.6f\n", ate.stats.rmse, config.camera.fx);
  return argc == 4 ? 0 : 1;
}
)";

/// A circle of 50 poses, 0.1 s apart; the estimate off by a wobble of `noise` metres.
std::string circle(double noise) {
  std::string text;
  for (int i = 0; i < 50; ++i) {
    const double a = 0.1 * i;
    text += fmt::format("{:.4f} {:.6f} {:.6f} {:.6f} 0 0 0 1\n", 100 + 0.1 * i, std::cos(a) + noise * std::sin(7 * a),
                        std::sin(a), 0.2 + noise * std::cos(5 * a));
  }
  return text;
}

TEST(InstalledPackage, AProjectBuildsAgainstTheInstalledLibrary) {
  test::TempDir tmp;
  const auto prefix = tmp / "prefix";
  const auto src = tmp / "consumer";
  std::filesystem::create_directories(src);
  test::writeText(src / "CMakeLists.txt", kConsumerCMake);
  test::writeText(src / "main.cpp", kConsumerMain);
  std::string out;
  ASSERT_EQ(test::runCommand(fmt::format("{} --install {} --prefix {}", TKGSLAM_CMAKE, TKGSLAM_BINARY_DIR,
                                         prefix.string()),
                             &out),
            0)
      << out;
  EXPECT_TRUE(std::filesystem::exists(prefix / "bin" / "tkgslam"));
  EXPECT_TRUE(std::filesystem::exists(prefix / "include" / "tkgslam" / "system" / "SlamSystem.h"));
  ASSERT_EQ(test::runCommand(fmt::format("{} -S {} -B {} -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH={}",
                                         TKGSLAM_CMAKE, src.string(), (tmp / "build").string(), prefix.string()),
                             &out),
            0)
      << out;
  ASSERT_EQ(test::runCommand(fmt::format("{} --build {}", TKGSLAM_CMAKE, (tmp / "build").string()), &out), 0) << out;

  test::writeText(tmp / "gt.txt", circle(0));
  test::writeText(tmp / "est.txt", circle(0.01));
  const std::string config = (test::sourceDir() / "configs" / "tum_fr1.yaml").string();
  ASSERT_EQ(test::runCommand(fmt::format("{} {} {} {}", (tmp / "build" / "consumer").string(),
                                         (tmp / "gt.txt").string(), (tmp / "est.txt").string(), config),
                             &out),
            0)
      << out;
  const double ate = eval::computeAte(io::readTumTrajectory((tmp / "gt.txt").string()),
                                      io::readTumTrajectory((tmp / "est.txt").string()))
                         .stats.rmse;
  EXPECT_GT(ate, 0.001);
  EXPECT_EQ(out, fmt::format("ate {:.9f} fx {:.6f}\n", ate, io::loadConfig(config).camera.fx));
}

}  // namespace
}  // namespace tkgslam
