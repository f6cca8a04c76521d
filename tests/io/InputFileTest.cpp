// Input files named by the user: a missing path, a folder and an unreadable file each get their own
// message (an ifstream opens a folder and reads nothing, which used to pass for an empty file).
#include <unistd.h>

#include <filesystem>
#include <functional>

#include <gtest/gtest.h>

#include "TestSupport.h"
#include "tkgslam/common/Error.h"
#include "tkgslam/io/ConfigFile.h"
#include "tkgslam/io/InputFile.h"
#include "tkgslam/io/TrajectoryFile.h"

namespace tkgslam {
namespace {

TEST(InputFile, SaysWhatIsWrongWithThePath) {
  test::TempDir tmp;
  const std::string missing = (tmp / "none.txt").string();
  const std::string folder = tmp.path().string();
  EXPECT_EQ(test::inputErrorOf([&] { io::openInputFile(missing, "config file"); }),
            "config file '" + missing + "' does not exist");
  EXPECT_EQ(test::inputErrorOf([&] { io::openInputFile(folder, "config file"); }),
            "config file '" + folder + "' is a folder, not a file");
  test::writeText(tmp / "ok.txt", "x");
  std::string text;
  EXPECT_TRUE(bool(io::openInputFile((tmp / "ok.txt").string(), "x") >> text));
  EXPECT_EQ(text, "x");
  if (geteuid() != 0) {  // root reads anything
    const auto locked = tmp / "locked.txt";
    test::writeText(locked, "x");
    std::filesystem::permissions(locked, std::filesystem::perms::none);
    EXPECT_EQ(test::inputErrorOf([&] { io::openInputFile(locked.string(), "map file"); }),
              "map file '" + locked.string() + "' cannot be read");
  }
  // The readers use it: a folder given as a trajectory or a config is named as one.
  EXPECT_NE(test::inputErrorOf([&] { io::readTumTrajectory(folder); }).find("is a folder, not a file"), std::string::npos);
  EXPECT_NE(test::inputErrorOf([&] { io::loadConfig(folder); }).find("is a folder, not a file"), std::string::npos);
}

}  // namespace
}  // namespace tkgslam
