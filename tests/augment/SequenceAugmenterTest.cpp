// The augmenter's options are checked before anything is done: cutting the people out of the photos
// (detector + GrabCut) takes a while, and a typo in a size must not cost that wait.
#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "TestSupport.h"
#include "tkgslam/augment/SequenceAugmenter.h"
#include "tkgslam/common/Error.h"

namespace tkgslam {
namespace {

TEST(SequenceAugmenter, OptionsOutOfRangeAreRefused) {
  augment::AugmentOptions o;
  EXPECT_NO_THROW(augment::checkAugmentOptions(o));
  o.max_size = 1.5;  // a person taller than the image: allowed up to 1.5 image heights
  EXPECT_NO_THROW(augment::checkAugmentOptions(o));
  for (auto [min_size, max_size] : {std::pair{0.0, 0.6}, {-0.1, 0.6}, {0.7, 0.6}, {0.3, 1.6}}) {
    o.min_size = min_size;
    o.max_size = max_size;
    EXPECT_THROW(augment::checkAugmentOptions(o), InputError) << min_size << " " << max_size;
  }
  o = augment::AugmentOptions{};
  o.people = 0;
  EXPECT_THROW(augment::checkAugmentOptions(o), InputError);
}

TEST(SequenceAugmenter, TheCliRefusesBadSizesBeforeCuttingPeopleOut) {
  TKGSLAM_REQUIRE_SHARED();
  test::TempDir tmp;
  std::string out;
  EXPECT_EQ(test::runCli("augment -c " + (test::sourceDir() / "configs" / "tum_fr1.yaml").string() + " -d " +
                             test::fr1xyz().string() + " -p " + (test::sharedDir() / "datasets" / "people").string() +
                             " -o " + (tmp / "aug").string() + " --min-size 0.9 --max-size 0.2",
                         &out),
            2);
  EXPECT_NE(out.find("0 < min_size <= max_size <= 1.5 (got --count 1, --min-size 0.9, --max-size 0.2)"),
            std::string::npos)
      << out;
  EXPECT_EQ(out.find("cutting the people out"), std::string::npos) << "the cut-outs were made first:\n" << out;
  EXPECT_FALSE(std::filesystem::exists(tmp / "aug")) << "nothing is written for a refused run";
}

/// Writes `tmp/seq`: 2 frames of `size` with depth of `depth_type`, ground-truth stamps followed by
/// `gt_unit` (e.g. "000000000": nanoseconds).
std::filesystem::path writeTinySequence(const test::TempDir& tmp, cv::Size size, int depth_type,
                                        const std::string& gt_unit = "") {
  const auto seq = tmp / "seq";
  std::filesystem::create_directories(seq / "rgb");
  std::filesystem::create_directories(seq / "depth");
  std::string rgb, depth, gt;
  for (int i = 0; i < 2; ++i) {
    const std::string t = std::to_string(100 + i);
    cv::imwrite((seq / "rgb" / (t + ".png")).string(), cv::Mat(size, CV_8UC3, cv::Scalar(90, 120, 150)));
    cv::imwrite((seq / "depth" / (t + ".png")).string(), cv::Mat(size, depth_type, cv::Scalar(200)));
    rgb += t + " rgb/" + t + ".png\n";
    depth += t + " depth/" + t + ".png\n";
    gt += t + gt_unit + " 0 0 0 0 0 0 1\n";
  }
  test::writeText(seq / "rgb.txt", rgb);
  test::writeText(seq / "depth.txt", depth);
  test::writeText(seq / "groundtruth.txt", gt);
  return seq;
}

/// Runs `augment` with the fr1 config from `seq` into `out_dir`.
int augmentCli(const std::filesystem::path& seq, const std::filesystem::path& out_dir, std::string& out) {
  return test::runCli("augment -c " + (test::sourceDir() / "configs" / "tum_fr1.yaml").string() + " -d " +
                          seq.string() + " -p " + (test::sharedDir() / "datasets" / "people").string() + " -o " +
                          out_dir.string(),
                      &out);
}

/// Runs `augment` with the fr1 config on a 2-frame sequence of `size` with depth of `depth_type`.
int augmentTinySequence(const test::TempDir& tmp, cv::Size size, int depth_type, std::string& out,
                        const std::string& gt_unit = "") {
  return augmentCli(writeTinySequence(tmp, size, depth_type, gt_unit), tmp / "aug", out);
}

// The people are projected with the config's camera and their depth written into the depth images:
// a sequence of another camera, or depth in a format it does not take, is refused up front.
TEST(SequenceAugmenter, TheCliRefusesASequenceItCannotUseBeforeCuttingPeopleOut) {
  TKGSLAM_REQUIRE_SHARED();
  std::string out;
  {
    test::TempDir tmp;
    EXPECT_EQ(augmentTinySequence(tmp, cv::Size(320, 240), CV_16UC1, out), 2) << out;
    EXPECT_NE(out.find("are 320x240 but the camera config says 640x480"), std::string::npos) << out;
    EXPECT_EQ(out.find("cutting the people out"), std::string::npos) << out;
  }
  {
    test::TempDir tmp;
    EXPECT_EQ(augmentTinySequence(tmp, cv::Size(640, 480), CV_8UC1, out), 2) << out;
    EXPECT_NE(out.find("must be single-channel 16-bit (or 32-bit float metres); it is 8-bit with 1 channel"),
              std::string::npos)
        << out;
    EXPECT_EQ(out.find("cutting the people out"), std::string::npos) << out;
  }
}

// The people are placed with the camera's true pose: a ground truth whose stamps are in another
// unit would give every frame the same (wrong) pose without a word.
TEST(SequenceAugmenter, TheCliRefusesAGroundTruthThatDoesNotCoverTheFrames) {
  TKGSLAM_REQUIRE_SHARED();
  test::TempDir tmp;
  std::string out;
  EXPECT_EQ(augmentTinySequence(tmp, cv::Size(640, 480), CV_16UC1, out, "000000000"), 2) << out;  // nanoseconds
  EXPECT_NE(out.find("augment: frame 0 (100.000000 s) has no ground-truth pose within 0.1 s"), std::string::npos)
      << out;
  EXPECT_EQ(out.find("cutting the people out"), std::string::npos) << out;
}

// Writing the composite over its own source would replace the original depth images and lists.
TEST(SequenceAugmenter, TheCliRefusesToWriteIntoTheSourceSequence) {
  TKGSLAM_REQUIRE_SHARED();
  test::TempDir tmp;
  std::string out;
  ASSERT_EQ(augmentTinySequence(tmp, cv::Size(640, 480), CV_16UC1, out), 0) << out;
  const std::string depth_list = test::readFile(tmp / "seq" / "depth.txt");
  EXPECT_EQ(augmentCli(tmp / "seq", tmp / "seq" / "." / "", out), 2);
  EXPECT_NE(out.find("is the --dataset folder"), std::string::npos) << out;
  EXPECT_EQ(test::readFile(tmp / "seq" / "depth.txt"), depth_list);
}

}  // namespace
}  // namespace tkgslam
