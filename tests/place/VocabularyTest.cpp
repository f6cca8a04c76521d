#include <random>
#include <set>

#include <gtest/gtest.h>

#include "tkgslam/common/Error.h"
#include "tkgslam/place/Vocabulary.h"

namespace tkgslam {
namespace {

// `clusters` random descriptors, each with `per_cluster` copies that differ in `flips` bits.
cv::Mat clusteredDescriptors(int clusters, int per_cluster, int flips, unsigned seed) {
  std::mt19937 rng(seed);
  cv::Mat out(clusters * per_cluster, 32, CV_8U);
  for (int c = 0; c < clusters; ++c) {
    uint8_t centre[32];
    for (auto& b : centre) b = uint8_t(rng());
    for (int i = 0; i < per_cluster; ++i) {
      uint8_t* row = out.ptr<uint8_t>(c * per_cluster + i);
      std::copy(centre, centre + 32, row);
      for (int f = 0; f < flips; ++f) {
        const int bit = int(rng() % 256);
        row[bit / 8] ^= uint8_t(1u << (bit % 8));
      }
    }
  }
  return out;
}

TEST(Vocabulary, SeparatesClustersOfDescriptorsIntoTheirOwnWords) {
  // Random 256-bit descriptors are ~128 bits apart; members differ from their centre in <= 12.
  const cv::Mat d = clusteredDescriptors(8, 100, 12, 3);
  place::VocabularyOptions o;
  o.branching = 8;
  o.depth = 1;
  const auto voc = place::Vocabulary::train(d, o);
  EXPECT_EQ(voc.words(), 8);
  std::set<int> words;
  for (int c = 0; c < 8; ++c) {
    const int w = voc.wordOf(d.ptr<uint8_t>(c * 100));
    words.insert(w);
    for (int i = 1; i < 100; ++i) EXPECT_EQ(voc.wordOf(d.ptr<uint8_t>(c * 100 + i)), w) << "cluster " << c;
  }
  EXPECT_EQ(words.size(), 8u);
}

TEST(Vocabulary, TrainsTheSameTreeTwiceAndGrowsWithDepth) {
  const cv::Mat d = clusteredDescriptors(50, 40, 30, 5);
  const auto a = place::Vocabulary::train(d);
  const auto b = place::Vocabulary::train(d);
  ASSERT_EQ(a.words(), b.words());
  for (int i = 0; i < d.rows; ++i) ASSERT_EQ(a.wordOf(d.ptr<uint8_t>(i)), b.wordOf(d.ptr<uint8_t>(i)));
  place::VocabularyOptions shallow;
  shallow.depth = 2;
  EXPECT_LE(place::Vocabulary::train(d, shallow).words(), 100);
  EXPECT_GT(a.words(), 100);  // 2000 descriptors: more leaves than two levels hold
  for (int i = 0; i < d.rows; ++i) {
    const int w = a.wordOf(d.ptr<uint8_t>(i));
    ASSERT_GE(w, 0);
    ASSERT_LT(w, a.words());
  }
}

TEST(Vocabulary, RefusesWhatIsNotAnOrbDescriptorAndIsEmptyWithoutData) {
  EXPECT_THROW(place::Vocabulary::train(cv::Mat(10, 32, CV_32F, cv::Scalar(0))), InputError);
  EXPECT_THROW(place::Vocabulary::train(cv::Mat(10, 16, CV_8U, cv::Scalar(0))), InputError);
  place::VocabularyOptions bad;
  bad.branching = 1;
  EXPECT_THROW(place::Vocabulary::train(cv::Mat(10, 32, CV_8U, cv::Scalar(0)), bad), InputError);
  const auto empty = place::Vocabulary::train(cv::Mat());
  EXPECT_EQ(empty.words(), 0);
  const uint8_t zeros[32] = {};
  EXPECT_EQ(empty.wordOf(zeros), -1);
  // Identical descriptors: one word, whatever the branching.
  EXPECT_EQ(place::Vocabulary::train(cv::Mat(50, 32, CV_8U, cv::Scalar(7))).words(), 1);
}

}  // namespace
}  // namespace tkgslam
