#pragma once
// A 3-D landmark (world frame, metres) observed by keyframes. All members are read and written
// with the Map's mutex held.
#include <cstdint>
#include <map>
#include <memory>

#include <opencv2/core.hpp>

#include "tkgslam/common/Pose.h"
#include "tkgslam/feature/ScalePyramid.h"

namespace tkgslam::data {

class KeyFrame;

/// Orders keyframes by id so that iteration is deterministic (never by address).
struct KeyFrameIdLess {
  bool operator()(const KeyFrame* a, const KeyFrame* b) const;
};

class MapPoint {
 public:
  MapPoint(long id, const Vec3& pos_w, KeyFrame* reference, const cv::Mat& descriptor);

  const long id;
  Vec3 pos_w;
  cv::Mat descriptor;           ///< 1 x 32, the observation descriptor closest to all others
  Vec3 normal = Vec3::Zero();   ///< mean viewing direction (unit), world frame
  float min_distance = 0, max_distance = 0;  ///< scale-invariance range, metres
  std::map<KeyFrame*, int, KeyFrameIdLess> observations;  ///< keyframe -> keypoint index
  KeyFrame* reference = nullptr;
  long first_keyframe_id = 0;
  int visible = 1;  ///< frames in whose view the point was predicted
  int found = 1;    ///< frames in which it was matched
  bool bad = false;
  std::shared_ptr<MapPoint> replaced_by;  ///< set when fused into another point

  // Scratch used by tracking (tracking thread, under the map lock).
  long last_frame_seen = -1;
  long local_map_frame = -1;
  bool track_in_view = false;
  float track_x = 0, track_y = 0, track_x_right = 0, track_view_cos = 0;
  int track_level = 0;
  // Scratch used by local mapping.
  long fuse_for = -1;

  /// Observation weight as ORB-SLAM2 counts it: 2 for an observation with depth, else 1.
  int observationWeight() const;
  float foundRatio() const { return float(found) / float(visible); }
  /// Pyramid level at which the point is expected at distance `dist` (metres).
  int predictScale(double dist, const feature::ScalePyramid& pyr) const;
  /// Recomputes normal and distance range from the observing keyframes.
  void updateNormalAndDepth(const feature::ScalePyramid& pyr);
  /// Picks the observation descriptor with the least median distance to the others.
  void computeDistinctiveDescriptor();
};

/// Hamming distance of two 32-byte ORB descriptors.
inline int descriptorDistance(const uint8_t* a, const uint8_t* b) {
  uint64_t diff[4];
  for (int i = 0; i < 4; ++i) {
    uint64_t x, y;
    __builtin_memcpy(&x, a + 8 * i, 8);
    __builtin_memcpy(&y, b + 8 * i, 8);
    diff[i] = x ^ y;
  }
#if defined(__x86_64__) && !defined(__POPCNT__)
  // The x86-64 baseline has no POPCNT instruction, so __builtin_popcountll is a call into libgcc
  // (11 % of the tracking thread's time on a composite). Bit-parallel counting, inlined, is 4.6x
  // faster and exact; builds with -mpopcnt (or -march=...) and other CPUs use the instruction.
  uint64_t bytes = 0;  // per-byte bit counts of the four words (at most 32 per byte)
  for (uint64_t x : diff) {
    x -= (x >> 1) & 0x5555555555555555ULL;
    x = (x & 0x3333333333333333ULL) + ((x >> 2) & 0x3333333333333333ULL);
    bytes += (x + (x >> 4)) & 0x0F0F0F0F0F0F0F0FULL;
  }
  // Summed in 16-bit lanes: the total reaches 256, one more than a byte holds.
  const uint64_t lanes = (bytes & 0x00FF00FF00FF00FFULL) + ((bytes >> 8) & 0x00FF00FF00FF00FFULL);
  return int((lanes * 0x0001000100010001ULL) >> 48);
#else
  return __builtin_popcountll(diff[0]) + __builtin_popcountll(diff[1]) + __builtin_popcountll(diff[2]) +
         __builtin_popcountll(diff[3]);
#endif
}
inline int descriptorDistance(const cv::Mat& a, const cv::Mat& b) {
  return descriptorDistance(a.ptr<uint8_t>(), b.ptr<uint8_t>());
}

}  // namespace tkgslam::data
