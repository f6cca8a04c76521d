#include <chrono>
#include <thread>

#include <gtest/gtest.h>

#include "TestSupport.h"
#include "TinyTumSequence.h"
#include "tkgslam/common/Error.h"
#include "tkgslam/io/FramePrefetcher.h"

namespace tkgslam {
namespace {

using test::TempDir;

bool sameImage(const cv::Mat& a, const cv::Mat& b) {
  return a.size() == b.size() && a.type() == b.type() && cv::norm(a, b, cv::NORM_INF) == 0;
}

TEST(FramePrefetcher, DeliversTheRangeInOrderAsLoadReadsIt) {
  TempDir tmp;
  test::writeTinyTumSequence(tmp.path(), 7);
  const io::TumDataset ds(tmp.path().string());
  for (int ahead : {1, 3, 10}) {
    io::FramePrefetcher reader(ds, 2, 6, ahead);
    // Time for the reader to fill its buffer, so that the order of the frames held matters.
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    for (int i = 2; i < 6; ++i) {
      auto f = reader.next();
      ASSERT_TRUE(f.has_value()) << "ahead " << ahead << ", frame " << i;
      EXPECT_EQ(f->index, i);
      const io::RgbdImages got = f->take(), want = ds.load(i);
      EXPECT_EQ(got.timestamp, want.timestamp);
      EXPECT_TRUE(sameImage(got.bgr, want.bgr));
      EXPECT_TRUE(sameImage(got.gray, want.gray));
      EXPECT_TRUE(sameImage(got.depth_m, want.depth_m));
    }
    EXPECT_FALSE(reader.next().has_value());
  }
  io::FramePrefetcher empty(ds, 4, 4);
  EXPECT_FALSE(empty.next().has_value());
}

TEST(FramePrefetcher, AnUnreadableFrameCarriesLoadsErrorAndTheNextFramesFollow) {
  TempDir tmp;
  test::writeTinyTumSequence(tmp.path(), 4);
  const io::TumDataset ds(tmp.path().string());
  test::writeText(tmp.path() / "rgb" / "101.000000.jpg", "not an image");
  const std::string expected = test::inputErrorOf([&] { ds.load(1); });
  ASSERT_FALSE(expected.empty());
  io::FramePrefetcher reader(ds, 0, 4);
  EXPECT_NO_THROW(reader.next()->take());
  auto bad = reader.next();
  ASSERT_TRUE(bad.has_value());
  EXPECT_EQ(bad->index, 1);
  EXPECT_EQ(test::inputErrorOf([&] { bad->take(); }), expected);
  for (int i = 2; i < 4; ++i) EXPECT_EQ(reader.next()->take().timestamp, ds.timestamp(i));
}

TEST(FramePrefetcher, StopsReadingWhenDestroyedBeforeTheEnd) {
  TempDir tmp;
  test::writeTinyTumSequence(tmp.path(), 3);
  io::TumDatasetOptions o;
  o.loops = 100000;  // far more frames than are taken: the reader must stop, not read them all
  const io::TumDataset ds(tmp.path().string(), o);
  const auto t0 = std::chrono::steady_clock::now();
  {
    io::FramePrefetcher reader(ds, 0, ds.size(), 2);
    EXPECT_EQ(reader.next()->index, 0);
  }
  EXPECT_LT(std::chrono::steady_clock::now() - t0, std::chrono::seconds(5));
}

}  // namespace
}  // namespace tkgslam
