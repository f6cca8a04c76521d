#include "tkgslam/match/NearestDescriptors.h"

#include "tkgslam/data/MapPoint.h"

namespace tkgslam::match {

namespace {

// The loop both builds share; inlined into each so the distance compiles for that build's target.
template <class Distance>
__attribute__((always_inline)) inline NearestTwo scan(const uint8_t* query, const uint8_t* rows, size_t step, int n,
                                                      const char* skip, Distance distance) {
  NearestTwo r;
  for (int j = 0; j < n; ++j) {
    if (skip && skip[j]) continue;
    const int d = distance(query, rows + size_t(j) * step);
    if (d < r.best) {
      r.second = r.best;
      r.best = d;
      r.index = j;
    } else if (d < r.second) {
      r.second = d;
    }
  }
  return r;
}

__attribute__((target("popcnt"))) NearestTwo scanPopcnt(const uint8_t* query, const uint8_t* rows, size_t step, int n,
                                                        const char* skip) {
  return scan(query, rows, step, n, skip, [](const uint8_t* a, const uint8_t* b) __attribute__((always_inline)) {
    int d = 0;
    for (int i = 0; i < 4; ++i) {
      uint64_t x, y;
      __builtin_memcpy(&x, a + 8 * i, 8);
      __builtin_memcpy(&y, b + 8 * i, 8);
      d += __builtin_popcountll(x ^ y);
    }
    return d;
  });
}

NearestTwo scanPortable(const uint8_t* query, const uint8_t* rows, size_t step, int n, const char* skip) {
  return scan(query, rows, step, n, skip, [](const uint8_t* a, const uint8_t* b) { return data::descriptorDistance(a, b); });
}

}  // namespace

NearestTwo nearestTwoDescriptors(const uint8_t* query, const uint8_t* rows, size_t step, int n, const char* skip) {
  static const bool popcnt = __builtin_cpu_supports("popcnt");
  return popcnt ? scanPopcnt(query, rows, step, n, skip) : scanPortable(query, rows, step, n, skip);
}

}  // namespace tkgslam::match
