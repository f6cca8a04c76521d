// Output files: a write that fails (full disk, file-size limit, no folder) throws with the system's
// reason, and never leaves a part of a file where a whole one is expected.
#include <sys/resource.h>
#include <unistd.h>

#include <csignal>
#include <filesystem>
#include <functional>
#include <string>

#include <gtest/gtest.h>

#include "TestSupport.h"
#include "tkgslam/io/OutputFile.h"
#include "tkgslam/io/TrajectoryFile.h"

namespace tkgslam {
namespace {

/// Runs `fn` with the file-size limit at `bytes` (writes past it fail with EFBIG once SIGXFSZ is
/// ignored, as the CLI does), then restores both.
std::string inputErrorUnderSizeLimit(rlim_t bytes, const std::function<void()>& fn) {
  rlimit old{};
  getrlimit(RLIMIT_FSIZE, &old);
  const auto previous = std::signal(SIGXFSZ, SIG_IGN);
  rlimit limited = old;
  limited.rlim_cur = bytes;
  setrlimit(RLIMIT_FSIZE, &limited);
  const std::string error = test::inputErrorOf(fn);
  setrlimit(RLIMIT_FSIZE, &old);
  std::signal(SIGXFSZ, previous);
  return error;
}

TEST(OutputFile, WritesAndReplacesAWholeFile) {
  test::TempDir tmp;
  const std::string path = (tmp / "a.txt").string();
  io::writeOutputFile(path, "test file", "first\n");
  io::writeOutputFile(path, "test file", "second\n");
  EXPECT_EQ(test::readFile(path), "second\n");
  EXPECT_FALSE(std::filesystem::exists(path + ".part"));
}

TEST(OutputFile, AFailedWriteKeepsTheEarlierFileAndLeavesNoPart) {
  test::TempDir tmp;
  const std::string path = (tmp / "map.ply").string();
  io::writeOutputFile(path, "PLY file", "earlier\n");
  const std::string big(64 * 1024, 'x');
  EXPECT_EQ(inputErrorUnderSizeLimit(4096, [&] { io::writeOutputFile(path, "PLY file", big); }),
            "cannot write PLY file '" + path + "': File too large");
  EXPECT_EQ(test::readFile(path), "earlier\n");
  EXPECT_FALSE(std::filesystem::exists(path + ".part"));

  // The same through a writer of the library: no trajectory that ends short.
  std::vector<StampedPose> poses(2000, StampedPose{1.0, Pose::Identity()});
  const std::string traj = (tmp / "trajectory.txt").string();
  EXPECT_EQ(inputErrorUnderSizeLimit(4096, [&] { io::writeTumTrajectory(traj, poses); }),
            "cannot write trajectory file '" + traj + "': File too large");
  EXPECT_FALSE(std::filesystem::exists(traj));
  EXPECT_FALSE(std::filesystem::exists(traj + ".part"));
}

TEST(OutputFile, AWritableFileInAReadOnlyFolderIsWrittenInPlace) {
  if (geteuid() == 0) GTEST_SKIP() << "root writes into any folder";
  test::TempDir tmp;
  const auto folder = tmp / "locked";
  std::filesystem::create_directories(folder);
  const std::string path = (folder / "errors.txt").string();
  io::writeOutputFile(path, "error file", "earlier\n");
  std::filesystem::permissions(folder, std::filesystem::perms::owner_read | std::filesystem::perms::owner_exec);
  const std::string error = test::inputErrorOf([&] { io::writeOutputFile(path, "error file", "new\n"); });
  const std::string refused =
      test::inputErrorOf([&] { io::writeOutputFile((folder / "new.txt").string(), "error file", "x"); });
  std::filesystem::permissions(folder, std::filesystem::perms::owner_all);
  EXPECT_EQ(error, "");
  EXPECT_EQ(test::readFile(path), "new\n");
  EXPECT_EQ(refused, "cannot write error file '" + (folder / "new.txt").string() + "': Permission denied");
}

TEST(OutputFile, ADeviceIsWrittenDirectly) {
  if (!std::filesystem::exists("/dev/full") || !std::filesystem::exists("/dev/null")) {
    GTEST_SKIP() << "/dev/full or /dev/null not found";
  }
  EXPECT_EQ(test::inputErrorOf([] { io::writeOutputFile("/dev/full", "plot", "<svg/>"); }),
            "cannot write plot '/dev/full': No space left on device");
  EXPECT_EQ(test::inputErrorOf([] { io::writeOutputFile("/dev/null", "plot", "<svg/>"); }), "");
  EXPECT_FALSE(std::filesystem::exists("/dev/null.part"));
  EXPECT_FALSE(std::filesystem::exists("/dev/full.part"));
}

TEST(OutputFile, SaysWhatIsWrongWithThePath) {
  test::TempDir tmp;
  const std::string folder = tmp.path().string();
  const std::string nowhere = (tmp / "none" / "a.txt").string();
  EXPECT_EQ(test::inputErrorOf([&] { io::writeOutputFile(folder, "report", "x"); }),
            "cannot write report '" + folder + "': it is a folder");
  EXPECT_EQ(test::inputErrorOf([&] { io::writeOutputFile(nowhere, "report", "x"); }),
            "cannot write report '" + nowhere + "': No such file or directory");
  EXPECT_EQ(test::inputErrorOf([&] { io::OutputLog log(nowhere, "frame log"); }),
            "cannot write frame log '" + nowhere + "': No such file or directory");
}

TEST(OutputLog, EachWriteIsOnDiskAndAFailureComesOutAtFinish) {
  test::TempDir tmp;
  const std::string path = (tmp / "frame_log.txt").string();
  io::OutputLog log(path, "frame log");
  log.write("# header\n");
  log.write("1.0 lost\n");
  EXPECT_EQ(test::readFile(path), "# header\n1.0 lost\n");  // before finish: a long run's log is live
  log.finish();
  log.finish();

  if (!std::filesystem::exists("/dev/full")) GTEST_SKIP() << "/dev/full not found";
  io::OutputLog full("/dev/full", "memory log");
  full.write("frame\trss_mib\n");
  full.write("100\t50.0\n");
  EXPECT_EQ(test::inputErrorOf([&] { full.finish(); }), "cannot write memory log '/dev/full': No space left on device");
}

}  // namespace
}  // namespace tkgslam
