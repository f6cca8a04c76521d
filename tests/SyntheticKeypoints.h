#pragma once
// Synthetic RGB-D keypoints for map-level tests: exact projections of known points.
#include "tkgslam/data/FrameFeatures.h"
#include "tkgslam/optimize/PoseOptimizer.h"

namespace tkgslam::test {

/// Appends a keypoint (octave 0, not excluded) at the exact ideal pixel of `q_c` (camera frame,
/// metres, z > 0), with its depth and virtual right-camera u = u - bf / z.
inline void addProjectedKeypoint(data::FrameFeatures& F, const Vec3& q_c, const optimize::PinholeIntrinsics& K) {
  const float u = float(K.fx * q_c.x() / q_c.z() + K.cx), v = float(K.fy * q_c.y() / q_c.z() + K.cy);
  F.raw.emplace_back(u, v, 31.f, -1.f, 0.f, 0);
  F.ideal.push_back(F.raw.back());
  F.depth.push_back(float(q_c.z()));
  F.u_right.push_back(float(u - K.bf / q_c.z()));
  F.excluded.push_back(0);
}

}  // namespace tkgslam::test
