#include <random>

#include <gtest/gtest.h>

#include "tkgslam/data/MapPoint.h"
#include "tkgslam/match/OrbMatcher.h"

namespace tkgslam {
namespace {

TEST(Hamming, CountsDifferingBits) {
  cv::Mat a(1, 32, CV_8U, cv::Scalar(0)), b(1, 32, CV_8U, cv::Scalar(0));
  EXPECT_EQ(data::descriptorDistance(a, b), 0);
  b.at<uchar>(0, 0) = 0xFF;   // 8 bits
  b.at<uchar>(0, 31) = 0x81;  // 2 bits
  EXPECT_EQ(data::descriptorDistance(a, b), 10);
  std::mt19937 rng(3);
  for (int k = 0; k < 100; ++k) {
    cv::Mat x(1, 32, CV_8U), y(1, 32, CV_8U);
    for (int i = 0; i < 32; ++i) x.at<uchar>(0, i) = uchar(rng()), y.at<uchar>(0, i) = uchar(rng());
    EXPECT_EQ(data::descriptorDistance(x, y), int(cv::norm(x, y, cv::NORM_HAMMING)));
  }
}

TEST(RotationConsistency, DropsMatchesOutsideTheDominantRotations) {
  std::vector<float> diffs;
  for (int i = 0; i < 50; ++i) diffs.push_back(12.0f + (i % 3));  // dominant bin around 12 degrees
  diffs.push_back(200.0f);                                        // lone outliers
  diffs.push_back(95.0f);
  std::vector<char> keep(diffs.size(), 1);
  match::OrbMatcher::rotationConsistency(diffs, keep);
  for (int i = 0; i < 50; ++i) EXPECT_TRUE(keep[i]);
  EXPECT_FALSE(keep[50]);
  EXPECT_FALSE(keep[51]);
}

}  // namespace
}  // namespace tkgslam
