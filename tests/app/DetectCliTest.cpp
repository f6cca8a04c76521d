#include <filesystem>

#include <gtest/gtest.h>

#include "TestSupport.h"

namespace tkgslam {
namespace {

std::string detectArgs(const test::TempDir& tmp) {
  return "detect --model " + (test::sharedDir() / "models" / "yolov5n-coco-640.onnx").string() + " -o " +
         (tmp / "det").string() + " ";
}

TEST(DetectCli, FindsThePeopleInARealPhotoAndDrawsThem) {
  TKGSLAM_REQUIRE_SHARED();
  test::TempDir tmp;
  std::string out;
  ASSERT_EQ(test::runCli(detectArgs(tmp) + (test::sharedDir() / "datasets" / "people" / "bus.jpg").string(), &out), 0)
      << out;
  EXPECT_NE(out.find("class  0 score 0."), std::string::npos) << out;  // class 0: person
  EXPECT_GT(std::filesystem::file_size(tmp / "det" / "bus_det.png"), 10000u);
}

TEST(DetectCli, ADepthImageIsRefusedNotScaledToEightBits) {
  TKGSLAM_REQUIRE_SHARED();
  test::TempDir tmp;
  const auto depth_dir = test::fr1xyz() / "depth";
  const auto depth = std::filesystem::directory_iterator(depth_dir)->path();
  std::string out;
  EXPECT_EQ(test::runCli(detectArgs(tmp) + depth.string(), &out), 2) << out;
  EXPECT_NE(out.find("is not an 8-bit image (a depth image?): it is 16-bit with 1 channel"), std::string::npos) << out;
}

}  // namespace
}  // namespace tkgslam
