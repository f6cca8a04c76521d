// The augmenter's options are checked before anything is done: cutting the people out of the photos
// (detector + GrabCut) takes a while, and a typo in a size must not cost that wait.
#include <gtest/gtest.h>

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
  EXPECT_EQ(out.find("person cut-outs"), std::string::npos) << "the cut-outs were made first:\n" << out;
  EXPECT_FALSE(std::filesystem::exists(tmp / "aug")) << "nothing is written for a refused run";
}

}  // namespace
}  // namespace tkgslam
