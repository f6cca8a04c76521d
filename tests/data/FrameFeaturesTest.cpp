#include <algorithm>
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "tkgslam/data/FrameFeatures.h"

namespace tkgslam {
namespace {

// The grid query against a scan of every keypoint: the same keypoints, in the grid's order (cells
// row by row, ascending index within a cell; matching breaks ties by this order).
TEST(FrameFeatures, RadiusQueriesFindWhatAScanFindsInTheGridsOrder) {
  camera::CameraParams p;
  p.fx = p.fy = 520;
  p.cx = 320;
  p.cy = 240;
  const camera::PinholeCamera camera(p);
  data::FrameFeatures f;
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> ux(-5.f, 645.f), uy(-5.f, 485.f);  // a few outside the image
  std::uniform_int_distribution<int> level(0, 7);
  for (int i = 0; i < 1500; ++i) {
    cv::KeyPoint kp(ux(rng), uy(rng), 31.f, -1.f, 0.f, level(rng));
    if (i % 50 == 7) kp.pt = f.ideal[size_t(i - 1)].pt;  // same position as the one before
    f.raw.push_back(kp);
    f.ideal.push_back(kp);
  }
  data::indexFeatures(f, camera);
  const auto cellOf = [&](const cv::Point2f& q) {
    return int(std::floor((q.y - f.min_y) * f.cell_h_inv)) * data::FrameFeatures::kGridCols +
           int(std::floor((q.x - f.min_x) * f.cell_w_inv));
  };
  const auto inImage = [&](const cv::Point2f& q) {
    return q.x >= f.min_x && q.y >= f.min_y && (q.x - f.min_x) * f.cell_w_inv < data::FrameFeatures::kGridCols &&
           (q.y - f.min_y) * f.cell_h_inv < data::FrameFeatures::kGridRows;
  };
  std::uniform_real_distribution<float> radius(0.5f, 60.f);
  int found = 0;
  for (int q = 0; q < 400; ++q) {
    const float x = ux(rng), y = uy(rng), r = radius(rng);
    const int lo = q % 3 == 0 ? -1 : level(rng), hi = q % 4 == 0 ? -1 : std::max(lo, level(rng));
    std::vector<int> want;
    for (int i = 0; i < f.size(); ++i) {
      const auto& kp = f.ideal[size_t(i)];
      if (!inImage(kp.pt) || (lo >= 0 && kp.octave < lo) || (hi >= 0 && kp.octave > hi)) continue;
      if (std::abs(kp.pt.x - x) < r && std::abs(kp.pt.y - y) < r) want.push_back(i);
    }
    std::stable_sort(want.begin(), want.end(),
                     [&](int a, int b) { return cellOf(f.ideal[size_t(a)].pt) < cellOf(f.ideal[size_t(b)].pt); });
    EXPECT_EQ(f.featuresInArea(x, y, r, lo, hi), want) << "query " << q << " at " << x << ", " << y << " r " << r;
    found += int(want.size());
  }
  EXPECT_GT(found, 2000);  // the queries do find keypoints
  data::FrameFeatures unindexed;
  EXPECT_TRUE(unindexed.featuresInArea(10, 10, 5).empty());
}

}  // namespace
}  // namespace tkgslam
