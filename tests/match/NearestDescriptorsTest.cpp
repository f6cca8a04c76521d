#include "tkgslam/match/NearestDescriptors.h"

#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "tkgslam/data/MapPoint.h"

namespace tkgslam {
namespace {

// Against the plain loop over data::descriptorDistance: random descriptors, rows near the query
// (a few bits flipped, so distances tie), a stride wider than a descriptor, and skipped rows.
TEST(NearestDescriptors, SameAsThePlainLoopWithTiesAndSkips) {
  std::mt19937 rng(3);
  std::uniform_int_distribution<int> byte(0, 255), bit(0, 255);
  constexpr size_t kStep = 40;  // 32 bytes used, 8 padding
  const int n = 500;
  std::vector<uint8_t> rows(n * kStep), query(32);
  for (auto& b : query) b = uint8_t(byte(rng));
  for (int j = 0; j < n; ++j) {
    uint8_t* r = rows.data() + j * kStep;
    for (int i = 0; i < 32; ++i) r[i] = j % 3 == 0 ? query[size_t(i)] : uint8_t(byte(rng));
    for (int f = 0; f < j % 7; ++f) {  // near the query: 0-6 bits flipped
      const int b = bit(rng);
      r[b / 8] ^= uint8_t(1 << (b % 8));
    }
    for (size_t i = 32; i < kStep; ++i) r[i] = 0xFF;  // padding must not count
  }
  std::vector<char> skip(n, 0);
  for (int round = 0; round < 3; ++round) {
    int best = 256, second = 256, index = -1;
    for (int j = 0; j < n; ++j) {
      if (skip[size_t(j)]) continue;
      const int d = data::descriptorDistance(query.data(), rows.data() + j * kStep);
      if (d < best) {
        second = best;
        best = d;
        index = j;
      } else if (d < second) {
        second = d;
      }
    }
    const auto r = match::nearestTwoDescriptors(query.data(), rows.data(), kStep, n, skip.data());
    EXPECT_EQ(r.best, best) << "round " << round;
    EXPECT_EQ(r.second, second) << "round " << round;
    EXPECT_EQ(r.index, index) << "round " << round;
    skip[size_t(index)] = 1;  // the next round must find the next one
  }
  EXPECT_EQ(match::nearestTwoDescriptors(query.data(), rows.data(), kStep, 1, nullptr).best, 0);  // row 0 = query
  const auto none = match::nearestTwoDescriptors(query.data(), rows.data(), kStep, 0, nullptr);
  EXPECT_EQ(none.index, -1);
  EXPECT_EQ(none.best, 256);
}

}  // namespace
}  // namespace tkgslam
