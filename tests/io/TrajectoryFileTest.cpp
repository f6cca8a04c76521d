#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "TestSupport.h"
#include "tkgslam/common/Error.h"
#include "tkgslam/io/TrajectoryFile.h"

namespace tkgslam {
namespace {

TEST(TrajectoryFile, WriteThenReadRoundTrips) {
  test::TempDir tmp;
  std::vector<StampedPose> poses(2);
  poses[0].timestamp = 1305031102.175304;
  poses[1].timestamp = 1305031102.211214;
  poses[1].T_wc.linear() = Eigen::AngleAxisd(2.5, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  poses[1].T_wc.translation() = Vec3(0.1, -0.2, 1.5);
  const auto path = (tmp / "traj.txt").string();
  io::writeTumTrajectory(path, poses);

  std::ifstream in(path);
  std::string header, line;
  std::getline(in, header);
  std::getline(in, line);
  EXPECT_EQ(line.substr(0, 18), "1305031102.175304 ");  // 6-decimal stamps

  const auto back = io::readTumTrajectory(path);
  ASSERT_EQ(back.size(), 2u);
  EXPECT_NEAR(back[1].timestamp, poses[1].timestamp, 1e-6);
  EXPECT_NEAR(back[1].q_xyzw.norm(), 1.0, 1e-9);
  EXPECT_GE(back[1].q_xyzw[3], 0.0);
  EXPECT_TRUE(back[1].pose().isApprox(poses[1].T_wc, 1e-8));
  // In memory, the same entries as written and read back (to the file's 9 decimals).
  EXPECT_EQ(line, io::formatTumPose(poses[0]));
  const auto entries = io::toTrajectoryEntries(poses);
  ASSERT_EQ(entries.size(), 2u);
  EXPECT_TRUE(entries[1].t.isApprox(back[1].t, 1e-8));
  EXPECT_TRUE(entries[1].q_xyzw.isApprox(back[1].q_xyzw, 1e-8));
}

TEST(TrajectoryFile, AcceptsCommasTabsAndComments) {
  std::istringstream in("# header\n\n1.0,0,0,0,0,0,0,1\n0.5\t1 2 3 0 0 0 1\n");
  const auto t = io::parseTumTrajectory(in, "x");
  ASSERT_EQ(t.size(), 2u);
  EXPECT_DOUBLE_EQ(t[0].timestamp, 0.5);  // sorted
  EXPECT_DOUBLE_EQ(t[0].t.z(), 3.0);
}

TEST(TrajectoryFile, AcceptsWindowsLineEndsAndAByteOrderMark) {
  std::istringstream with_comment("\xEF\xBB\xBF# header\r\n1.0 0 0 0 0 0 0 1\r\n2.0 1 0 0 0 0 0 1\r\n");
  const auto t = io::parseTumTrajectory(with_comment, "x");
  ASSERT_EQ(t.size(), 2u);
  EXPECT_DOUBLE_EQ(t[1].t.x(), 1.0);
  EXPECT_DOUBLE_EQ(t[1].q_xyzw[3], 1.0);
  std::istringstream data_first("\xEF\xBB\xBF" "1.5 0 0 0 0 0 0 1\n");
  ASSERT_EQ(io::parseTumTrajectory(data_first, "x").size(), 1u);
  // Only a whole mark is skipped: a stray byte stays part of the first value.
  std::istringstream stray("\xEF" "1.5 0 0 0 0 0 0 1\n");
  EXPECT_NE(test::inputErrorOf([&] { io::parseTumTrajectory(stray, "x"); }).find("x:1: value 1"), std::string::npos);
}

TEST(TrajectoryFile, MalformedLinesNameFileAndLine) {
  std::istringstream short_line("1 2 3 4 5 6 7 8\n2 0 0 0 0 0 1\n");
  try {
    io::parseTumTrajectory(short_line, "est.txt");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("est.txt:2"), std::string::npos) << e.what();
  }
  std::istringstream nan_line("1 nan 0 0 0 0 0 1\n");
  EXPECT_THROW(io::parseTumTrajectory(nan_line, "x"), InputError);
  std::istringstream text_line("1 0 0 zero 0 0 0 1\n");
  EXPECT_THROW(io::parseTumTrajectory(text_line, "x"), InputError);
  EXPECT_THROW(io::readTumTrajectory("/nonexistent/traj.txt"), InputError);
}

}  // namespace
}  // namespace tkgslam
