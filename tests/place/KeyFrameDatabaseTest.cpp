#include <algorithm>

#include <gtest/gtest.h>

#include "TestSupport.h"
#include "tkgslam/feature/OrbExtractor.h"
#include "tkgslam/io/TumDataset.h"
#include "tkgslam/place/KeyFrameDatabase.h"

namespace tkgslam {
namespace {

// Features of fr1_xyz frames (descriptors only: all the database reads).
class KeyFrameDatabaseOnFr1 : public ::testing::Test {
 protected:
  void SetUp() override {
    TKGSLAM_REQUIRE_SHARED();
    dataset_ = std::make_unique<io::TumDataset>(test::fr1xyz().string());
  }

  std::shared_ptr<data::FrameFeatures> featuresOf(int i) const {
    auto f = std::make_shared<data::FrameFeatures>();
    f->descriptors = extractor_.extract(dataset_->load(i).gray).descriptors;
    return f;
  }

  // "Keyframes" at every 40th frame, with ids 100, 103, 106, ... (ids need not be consecutive).
  std::vector<place::DatabaseEntry> keyframes(int count) const {
    std::vector<place::DatabaseEntry> out;
    for (int k = 0; k < count; ++k) out.push_back({100 + 3L * k, featuresOf(40 * k)});
    return out;
  }

  feature::OrbExtractor extractor_{feature::OrbParams{}};
  std::unique_ptr<io::TumDataset> dataset_;
};

TEST_F(KeyFrameDatabaseOnFr1, AnswersKeyFrameIdsAndOnlyAmongThoseAskedAbout) {
  const auto entries = keyframes(19);
  place::KeyFrameDatabase db;
  ASSERT_TRUE(db.update(entries));
  EXPECT_EQ(db.size(), 19u);
  EXPECT_EQ(db.newestId(), 154);
  int top3 = 0;
  for (int k = 0; k < 19; ++k) {
    // A frame the database never saw, 3 frames after keyframe k.
    const auto query = featuresOf(40 * k + 3);
    const auto ids = db.mostSimilar(*query, 3);
    ASSERT_EQ(ids.size(), 3u);
    top3 += std::count(ids.begin(), ids.end(), 100 + 3L * k) > 0;
    // Asked only about the other keyframes: k's is not answered, and still 3 are.
    std::vector<long> others;
    for (const auto& e : entries) {
      if (e.id != 100 + 3L * k) others.push_back(e.id);
    }
    const auto among = db.mostSimilar(*query, 3, &others);
    EXPECT_EQ(among.size(), 3u);
    for (const long id : among) EXPECT_NE(id, 100 + 3L * k);
  }
  // As place::KeyFrameIndex finds them (measured: 19 of 19).
  EXPECT_GE(top3, 18) << "of 19 queries had their own keyframe in the top 3";
}

TEST_F(KeyFrameDatabaseOnFr1, FollowsAGrowingMapAndRetrainsOnceItHasDoubled) {
  const auto entries = keyframes(12);
  place::KeyFrameDatabase db(/*retrain_growth=*/2.0);
  ASSERT_TRUE(db.update({entries.begin(), entries.begin() + 6}));
  const int words = db.words();
  // Three more: indexed with the vocabulary of the first six, which are not indexed twice.
  EXPECT_FALSE(db.update({entries.begin(), entries.begin() + 9}));
  EXPECT_EQ(db.size(), 9u);
  EXPECT_EQ(db.words(), words);
  EXPECT_EQ(db.newestId(), entries[8].id);
  for (int k = 6; k < 9; ++k) {
    const auto ids = db.mostSimilar(*entries[size_t(k)].features, 1);
    ASSERT_EQ(ids.size(), 1u);
    EXPECT_EQ(ids[0], entries[size_t(k)].id) << "a keyframe added after training is most like itself";
  }
  // Twelve: twice what the vocabulary was trained on.
  EXPECT_TRUE(db.update(entries));
  EXPECT_EQ(db.size(), 12u);
  EXPECT_NE(db.words(), words);
}

TEST(KeyFrameDatabase, WithoutDescriptorsNothingIsIndexed) {
  place::KeyFrameDatabase db;
  EXPECT_FALSE(db.update({{1, nullptr}, {2, std::make_shared<data::FrameFeatures>()}}));
  EXPECT_FALSE(db.trained());
  EXPECT_EQ(db.size(), 0u);
  EXPECT_TRUE(db.mostSimilar(data::FrameFeatures{}, 5).empty());
}

}  // namespace
}  // namespace tkgslam
