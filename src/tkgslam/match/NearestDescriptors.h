#pragma once
// Brute-force search for the two nearest ORB descriptors (Hamming distance) among a set: the inner
// loop of descriptor matching (tracking's reference keyframe, relocalisation, loop verification).
#include <cstddef>
#include <cstdint>

namespace tkgslam::match {

struct NearestTwo {
  int best = 256;    ///< smallest distance (256 = none)
  int second = 256;  ///< second smallest (the ratio test's)
  int index = -1;    ///< row of the smallest; the first such row on ties
};

/// The nearest two of `rows` descriptors (32 bytes each, `step` bytes apart) to `query`, rows with
/// skip[j] != 0 left out (skip may be null). Exact: on CPUs with POPCNT an instruction per 64 bits
/// (chosen at run time: the portable build's baseline has none), otherwise bit-parallel counting.
NearestTwo nearestTwoDescriptors(const uint8_t* query, const uint8_t* rows, size_t step, int n, const char* skip);

}  // namespace tkgslam::match
