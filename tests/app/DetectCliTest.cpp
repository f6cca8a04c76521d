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

TEST(DetectCli, AnExtraPassAtASmallerInputIsNamedAndItsSizeChecked) {
  TKGSLAM_REQUIRE_SHARED();
  test::TempDir tmp;
  const std::string bus = (test::sharedDir() / "datasets" / "people" / "bus.jpg").string();
  std::string out;
  ASSERT_EQ(test::runCli(detectArgs(tmp) + "--extra-size 320 " + bus, &out), 0) << out;
  EXPECT_NE(out.find("at 480 x 640 and long side 320)"), std::string::npos) << out;
  EXPECT_NE(out.find("class  0 score 0."), std::string::npos) << out;
  EXPECT_EQ(test::runCli(detectArgs(tmp) + "--extra-size 600 " + bus, &out), 2) << out;
  EXPECT_NE(out.find("input size 600 must be a multiple of 32"), std::string::npos) << out;
}

TEST(DetectCli, AFolderStandsForTheImagesInIt) {
  TKGSLAM_REQUIRE_SHARED();
  test::TempDir tmp;
  const auto photos = tmp / "photos";
  std::filesystem::create_directories(photos);
  std::filesystem::copy_file(test::sharedDir() / "datasets" / "people" / "bus.jpg", photos / "b.JPG");
  std::filesystem::copy_file(test::sharedDir() / "datasets" / "people" / "zidane.jpg", photos / "a.jpg");
  test::writeText(photos / "notes.txt", "not an image");
  std::string out;
  ASSERT_EQ(test::runCli(detectArgs(tmp) + photos.string(), &out), 0) << out;
  EXPECT_LT(out.find("a.jpg: "), out.find("b.JPG: ")) << out;  // in name order
  EXPECT_TRUE(std::filesystem::exists(tmp / "det" / "a_det.png"));
  EXPECT_TRUE(std::filesystem::exists(tmp / "det" / "b_det.png"));
  EXPECT_EQ(out.find("notes"), std::string::npos) << out;
  std::filesystem::create_directories(tmp / "empty");
  EXPECT_EQ(test::runCli(detectArgs(tmp) + (tmp / "empty").string(), &out), 2) << out;
  EXPECT_NE(out.find("has no images"), std::string::npos) << out;
  // b.JPG and a b.png elsewhere would both be drawn into b_det.png.
  std::filesystem::copy_file(photos / "a.jpg", tmp / "b.png");
  EXPECT_EQ(test::runCli(detectArgs(tmp) + photos.string() + " " + (tmp / "b.png").string(), &out), 2) << out;
  EXPECT_NE(out.find("would both be drawn into"), std::string::npos) << out;
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

// The default model path is relative to the working folder: from elsewhere, say so and name the
// option, rather than "does not exist" for a path the user never typed. The same for augment's config.
TEST(DetectCli, AMissingDefaultFileNamesItsOption) {
  test::TempDir tmp;
  const auto work = tmp / "a" / "b";  // a folder without ../shared
  std::filesystem::create_directories(work);
  const std::string cd = "cd " + work.string() + " && " + TKGSLAM_CLI;
  std::string out;
  EXPECT_EQ(test::runCommand(cd + " detect photo.jpg", &out), 2) << out;
  EXPECT_NE(out.find("--model was not given and its default '../shared/models/yolov5n-coco-640.onnx' is not there"),
            std::string::npos)
      << out;
  EXPECT_EQ(test::runCommand(cd + " augment -d seq -p people -o out", &out), 2) << out;
  EXPECT_NE(out.find("--config was not given and its default 'configs/tum_fr1.yaml' is not there"), std::string::npos)
      << out;
  // A path that was given is reported as it is.
  EXPECT_EQ(test::runCommand(cd + " detect --model nope.onnx photo.jpg", &out), 2) << out;
  EXPECT_NE(out.find("model file 'nope.onnx' (" + (work / "nope.onnx").string() + ") does not exist"),
            std::string::npos)
      << out;
  EXPECT_EQ(test::runCommand(cd + " detect --model " + tmp.path().string() + " photo.jpg", &out), 2) << out;
  EXPECT_NE(out.find("model file '" + tmp.path().string() + "' is a folder"), std::string::npos) << out;
}

}  // namespace
}  // namespace tkgslam
