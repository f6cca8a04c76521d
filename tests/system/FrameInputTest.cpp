// Frames an application builds itself (a live camera) are checked like the files `run` reads: a raw
// 16-bit depth image, a frame of another size or a timestamp going back is an error naming the image,
// not out-of-bounds reads; and each tracked frame comes out with its pose.
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "TestSupport.h"
#include "tkgslam/eval/Ate.h"
#include "tkgslam/io/ConfigFile.h"
#include "tkgslam/io/TrajectoryFile.h"
#include "tkgslam/system/FrameInput.h"
#include "tkgslam/system/SlamSystem.h"

namespace tkgslam {
namespace {

const cv::Size kSize(64, 48);

io::RgbdImages validFrame(double timestamp) {
  io::RgbdImages f;
  f.timestamp = timestamp;
  f.bgr = cv::Mat(kSize, CV_8UC3, cv::Scalar(10, 20, 30));
  f.depth_m = cv::Mat(kSize, CV_32F, cv::Scalar(1.5));
  return f;
}

TEST(FrameInput, FillsInTheGreyImageAndPassesAValidFrame) {
  const auto f = checkFrameImages(validFrame(1.0), kSize, 0.5);
  ASSERT_EQ(f.gray.type(), CV_8UC1);
  EXPECT_EQ(f.gray.size(), kSize);
  EXPECT_EQ(int(f.gray.at<uchar>(0, 0)), 22);  // 0.114 * 10 + 0.587 * 20 + 0.299 * 30 = 21.85
  EXPECT_EQ(f.depth_m.at<float>(0, 0), 1.5f);
}

TEST(FrameInput, SaysWhichImageIsWrongAndHow) {
  auto raw = validFrame(1.0);
  raw.depth_m = cv::Mat(kSize, CV_16U, cv::Scalar(7500));
  EXPECT_EQ(test::inputErrorOf([&] { checkFrameImages(raw, kSize, std::nullopt); }),
            "processFrame: depth_m must be 32-bit float metres with 1 channel; it is 16-bit with 1 channel (raw "
            "depth: convertTo(depth_m, CV_32F, 1.0 / depth_factor))");
  auto small = validFrame(1.0);
  small.bgr = cv::Mat(24, 32, CV_8UC3);
  EXPECT_EQ(test::inputErrorOf([&] { checkFrameImages(small, kSize, std::nullopt); }),
            "processFrame: bgr is 32x24 but the camera config says 64x48");
  auto rgba = validFrame(1.0);
  rgba.bgr = cv::Mat(kSize, CV_8UC4);
  EXPECT_EQ(test::inputErrorOf([&] { checkFrameImages(rgba, kSize, std::nullopt); }),
            "processFrame: bgr must be 8-bit with 3 channels (BGR); it is 8-bit with 4 channels");
  auto no_depth = validFrame(1.0);
  no_depth.depth_m.release();
  EXPECT_EQ(test::inputErrorOf([&] { checkFrameImages(no_depth, kSize, std::nullopt); }),
            "processFrame: depth_m is empty (expected 32-bit float metres with 1 channel)");
  EXPECT_EQ(test::inputErrorOf([&] { checkFrameImages(validFrame(1.0), kSize, 1.0); }),
            "processFrame: timestamp 1.000000 is not after the previous frame's (1.000000)");
  EXPECT_EQ(test::inputErrorOf(
                [&] { checkFrameImages(validFrame(std::numeric_limits<double>::quiet_NaN()), kSize, std::nullopt); }),
            "processFrame: the timestamp is not a finite number");
}

TEST(FrameInput, DepthsThatAreNotNumbersBecomeNoDepthInACopy) {
  auto f = validFrame(1.0);
  f.depth_m.at<float>(1, 2) = std::numeric_limits<float>::quiet_NaN();
  f.depth_m.at<float>(3, 4) = std::numeric_limits<float>::infinity();
  const auto checked = checkFrameImages(f, kSize, std::nullopt);
  EXPECT_EQ(checked.depth_m.at<float>(1, 2), 0.0f);
  EXPECT_EQ(checked.depth_m.at<float>(3, 4), 0.0f);
  EXPECT_EQ(checked.depth_m.at<float>(0, 0), 1.5f);
  EXPECT_TRUE(std::isnan(f.depth_m.at<float>(1, 2)));  // the caller's buffer is left as it was
}

TEST(FrameInput, ABadFrameIsRefusedAndTheNextOneTracked) {
  TKGSLAM_REQUIRE_SHARED();
  SlamConfig config = io::loadConfig((test::sourceDir() / "configs" / "tum_fr1.yaml").string());
  config.deterministic = true;
  io::TumDatasetOptions options;
  options.depth_factor = config.depth.factor;
  const io::TumDataset sequence(test::fr1xyz().string(), options);
  SlamSystem slam(config);
  std::vector<StampedPose> live;
  for (int i = 0; i < 60; ++i) {
    io::RgbdImages frame = sequence.load(i);
    frame.gray.release();  // made from bgr
    if (i == 30) {
      io::RgbdImages raw = frame;
      raw.depth_m.convertTo(raw.depth_m, CV_16U, config.depth.factor);
      EXPECT_NE(test::inputErrorOf([&] { slam.processFrame(raw); }).find("depth_m must be 32-bit float"),
                std::string::npos);
    }
    for (const auto& outcome : slam.processFrame(frame)) {
      ASSERT_TRUE(outcome.result.T_wc) << "frame " << outcome.index << " tracked without a pose";
      live.push_back({outcome.timestamp, *outcome.result.T_wc});
    }
  }
  slam.finish();
  EXPECT_EQ(slam.framesProcessed(), 60);  // the refused frame is not counted
  ASSERT_EQ(live.size(), 60u);
  // The live poses are those tracking had; the final ones differ by what local BA moved since and
  // by the end-of-run repairs.
  const auto final_poses = slam.trajectory();
  ASSERT_EQ(final_poses.size(), live.size());
  double largest = 0;
  for (size_t i = 0; i < live.size(); ++i) {
    largest = std::max(largest, (live[i].T_wc.translation() - final_poses[i].T_wc.translation()).norm());
  }
  EXPECT_LT(largest, 0.01);  // 3.6 mm (deterministic)
  const auto gt = io::readTumTrajectory((test::fr1xyz() / "groundtruth.txt").string());
  EXPECT_LT(eval::computeAte(gt, io::toTrajectoryEntries(live)).stats.rmse, 0.02);
}

TEST(FrameInput, TheExampleApplicationPrintsEachTrackedFramesPose) {
  TKGSLAM_REQUIRE_SHARED();
  test::TempDir tmp;
  const auto live = tmp / "live.txt";
  std::string out;
  // Poses on stdout, logs on stderr: the output is a trajectory file as it is.
  ASSERT_EQ(test::runCommand("(" + std::string(TKGSLAM_EXAMPLE_TRACK_FRAMES) + " " +
                                 (test::sourceDir() / "configs" / "tum_fr1.yaml").string() + " " +
                                 test::fr1xyz().string() + " 100 > " + live.string() + ")",
                             &out),
            0)
      << out;
  const auto est = io::readTumTrajectory(live.string());
  EXPECT_EQ(est.size(), 100u);
  const auto gt = io::readTumTrajectory((test::fr1xyz() / "groundtruth.txt").string());
  EXPECT_LT(eval::computeAte(gt, est).stats.rmse, 0.02);
  EXPECT_EQ(test::runCommand(std::string(TKGSLAM_EXAMPLE_TRACK_FRAMES) + " /nonexistent.yaml .", &out), 2);
  EXPECT_NE(out.find("config file '/nonexistent.yaml' does not exist"), std::string::npos) << out;
}

}  // namespace
}  // namespace tkgslam
