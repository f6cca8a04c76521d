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
  // All 256 bits apart, and all but one (the counting must not wrap at a byte).
  EXPECT_EQ(data::descriptorDistance(a, cv::Mat(1, 32, CV_8U, cv::Scalar(0xFF))), 256);
  cv::Mat c(1, 32, CV_8U, cv::Scalar(0xFF));
  c.at<uchar>(0, 17) = 0xFE;
  EXPECT_EQ(data::descriptorDistance(a, c), 255);
  std::mt19937 rng(3);
  for (int k = 0; k < 1000; ++k) {
    cv::Mat x(1, 32, CV_8U), y(1, 32, CV_8U);
    // Random pairs, and pairs a few flipped bits from equal, from complementary and from half apart.
    const unsigned flip[] = {0x00u, 0xFFu, 0x5Au};
    for (int i = 0; i < 32; ++i) {
      x.at<uchar>(0, i) = uchar(rng());
      const unsigned noise = rng() % 5 == 0 ? 1u << (rng() % 8) : 0u;
      y.at<uchar>(0, i) = uchar(k % 4 == 3 ? rng() : x.at<uchar>(0, i) ^ flip[k % 4] ^ noise);
    }
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
