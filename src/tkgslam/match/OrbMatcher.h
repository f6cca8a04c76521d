#pragma once
// Descriptor matching between frames, keyframes and map points (ORB-SLAM2's strategies):
// projection search in a window scaled by the pyramid level, Hamming thresholds, a ratio test,
// and a rotation-consistency histogram that drops matches whose keypoint angles disagree.
#include <memory>
#include <vector>

#include "tkgslam/camera/PinholeCamera.h"
#include "tkgslam/data/Frame.h"
#include "tkgslam/data/KeyFrame.h"
#include "tkgslam/data/Map.h"
#include "tkgslam/feature/ScalePyramid.h"

namespace tkgslam::match {

constexpr int kThHigh = 100;  ///< max Hamming distance for projection matches
constexpr int kThLow = 50;    ///< max Hamming distance for descriptor-only matches

class OrbMatcher {
 public:
  OrbMatcher(const camera::PinholeCamera& camera, const feature::ScalePyramid& pyramid, double baseline_fx)
      : cam_(camera), pyr_(pyramid), bf_(baseline_fx) {}

  /// Motion-model tracking: projects the last frame's matched points into `cur` (whose pose is
  /// the prediction) and searches a window of `th` * scale pixels. Returns new matches.
  int searchByProjection(data::Frame& cur, const data::Frame& last, float th) const;

  /// Whether `mp` should be visible from a camera at T_cw (in front, in the image, within its scale
  /// range, viewed less than acos(min_view_cos) off its mean viewing direction); if so fills its
  /// track_* scratch (predicted pixel, virtual right u, level, view cosine) for searchByProjection.
  bool isInFrustum(data::MapPoint& mp, const Pose& T_cw, double min_view_cos) const;

  /// Local-map tracking: searches `points` (with track_* scratch filled by the caller) in `cur`.
  int searchByProjection(data::Frame& cur, const std::vector<std::shared_ptr<data::MapPoint>>& points,
                         float th) const;

  /// Appearance-only matching of a keyframe's map points to a frame's keypoints (brute force,
  /// ratio test 0.7, rotation check). Fills `matches` (per frame keypoint) and returns the count.
  int searchByDescriptors(const data::KeyFrame& kf, const data::Frame& cur,
                          std::vector<std::shared_ptr<data::MapPoint>>& matches) const;

  /// Projects `points` into `kf` and fuses duplicates: a keypoint already holding a point gets
  /// the one with more observations; a free keypoint gains the observation. Returns the fused count.
  int fuse(data::Map& map, data::KeyFrame& kf, const std::vector<std::shared_ptr<data::MapPoint>>& points,
           float th = 3.0f) const;

  /// Keeps only matches whose rotation falls in the three most common histogram bins.
  static void rotationConsistency(const std::vector<float>& angle_diffs, std::vector<char>& keep);

 private:
  const camera::PinholeCamera& cam_;
  const feature::ScalePyramid& pyr_;
  double bf_;
};

}  // namespace tkgslam::match
