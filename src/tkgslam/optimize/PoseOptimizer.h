#pragma once
// Pose-only optimisation (motion-only bundle adjustment) of one camera against fixed 3-D points:
// Gauss-Newton on SE(3) with a Huber kernel, re-classifying outliers by a chi-square test
// between rounds (ORB-SLAM2's 4 x 10 scheme; the kernel is dropped in the last two rounds).
#include <vector>

#include "tkgslam/common/Pose.h"
#include "tkgslam/optimize/PinholeIntrinsics.h"

namespace tkgslam::optimize {

/// One 2-D (or RGB-D "stereo") observation of a fixed world point.
struct PoseObservation {
  Vec3 p_w;                 ///< world point, metres
  Vec2 uv;                  ///< observed ideal pixel
  double u_right = -1;      ///< observed virtual right u (u - bf/depth); < 0 = monocular residual
  double information = 1;   ///< 1 / sigma^2 of the keypoint's pyramid level
};

struct PoseOptimizerOptions {
  int rounds = 4;
  int iterations = 10;
  double chi2_mono = 5.991;    ///< 95 % for 2 DOF
  double chi2_stereo = 7.815;  ///< 95 % for 3 DOF
};

/// Refines T_cw in place. `outlier` (resized to the observations) receives the final outlier
/// flags. Returns the number of inliers. Deterministic.
int optimizePose(const std::vector<PoseObservation>& obs, const PinholeIntrinsics& K, Pose& T_cw,
                 std::vector<char>& outlier, const PoseOptimizerOptions& options = {});

}  // namespace tkgslam::optimize
