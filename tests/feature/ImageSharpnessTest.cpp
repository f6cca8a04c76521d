#include <cmath>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <gtest/gtest.h>

#include "TestSupport.h"
#include "tkgslam/common/Error.h"
#include "tkgslam/feature/ImageSharpness.h"
#include "tkgslam/io/TumDataset.h"

namespace tkgslam {
namespace {

cv::Mat smeared(const cv::Mat& img, double angle_deg) {
  cv::Mat kernel = cv::Mat::zeros(31, 31, CV_32F);
  const double a = angle_deg * CV_PI / 180;
  const cv::Point2d d(15 * std::cos(a), 15 * std::sin(a));
  cv::line(kernel, cv::Point2d(15, 15) - d, cv::Point2d(15, 15) + d, cv::Scalar(1.0));
  kernel /= cv::sum(kernel)[0];
  cv::Mat out;
  cv::filter2D(img, out, -1, kernel);
  return out;
}

// A smear in any direction drops the measure well below the tracker's default threshold (0.3 of
// the recent sharp frames), while neighbouring sharp frames of the real sequence stay near 1.
TEST(ImageSharpness, MotionBlurInAnyDirectionStandsOutFromNeighbouringFrames) {
  TKGSLAM_REQUIRE_SHARED();
  io::TumDataset ds(test::fr1xyz().string());
  const cv::Mat a = cv::imread(ds.entry(0).rgb_path, cv::IMREAD_GRAYSCALE);
  const cv::Mat b = cv::imread(ds.entry(5).rgb_path, cv::IMREAD_GRAYSCALE);
  ASSERT_FALSE(a.empty());
  const double sa = feature::imageSharpness(a);
  EXPECT_GT(sa, 1000.0);
  const double ratio = feature::imageSharpness(b) / sa;
  EXPECT_GT(ratio, 0.6);
  EXPECT_LT(ratio, 1.6);
  for (double angle : {0.0, 30.0, 45.0, 90.0, 135.0, 170.0}) {
    EXPECT_LT(feature::imageSharpness(smeared(a, angle)) / sa, 0.25) << angle << " degrees";
  }
  // A mild defocus (3x3 box) is not motion blur.
  cv::Mat soft;
  cv::blur(a, soft, cv::Size(3, 3));
  EXPECT_GT(feature::imageSharpness(soft) / sa, 0.3);
  EXPECT_EQ(feature::imageSharpness(cv::Mat::zeros(480, 640, CV_8UC1)), 0.0);
}

TEST(ImageSharpness, RejectsNonGreyImages) {
  EXPECT_THROW(feature::imageSharpness(cv::Mat()), InputError);
  EXPECT_THROW(feature::imageSharpness(cv::Mat::zeros(10, 10, CV_8UC3)), InputError);
}

}  // namespace
}  // namespace tkgslam
