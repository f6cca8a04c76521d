#pragma once
// Local bundle adjustment over a window of keyframes and the points they see: our dense-Schur
// Levenberg-Marquardt (DenseSchurSolver.h) for the covisible windows local mapping builds, Ceres'
// sparse Schur for long sparse ones. The problem is a plain copy of the map state, so it can be
// solved without holding the map lock.
#include <vector>

#include "tkgslam/common/Pose.h"
#include "tkgslam/optimize/PoseOptimizer.h"

namespace tkgslam::optimize {

struct BundleObservation {
  int camera;               ///< index into BundleProblem::poses
  int point;                ///< index into BundleProblem::points
  Vec2 uv;                  ///< ideal pixel
  double u_right = -1;      ///< < 0 = monocular residual
  double information = 1;   ///< 1 / sigma^2
};

struct BundleProblem {
  std::vector<Pose> poses;        ///< T_cw per camera
  std::vector<char> fixed_pose;   ///< 1 = held constant
  std::vector<Vec3> points;       ///< world points
  std::vector<BundleObservation> observations;
};

struct BundleOptions {
  int iterations_first = 5;   ///< robust pass
  int iterations_second = 10; ///< pass after removing outliers
  double chi2_mono = 5.991;
  double chi2_stereo = 7.815;
  int threads = 1;  ///< Ceres' threads on the sparse path (the dense one runs on the caller's thread)
};

/// Whether the reduced camera system (the free poses after eliminating the points) is solved as a
/// dense matrix (solveDenseSchur): always for up to 40 free poses; for up to 400 when eliminating
/// the points is the larger cost (sum over points of the squared number of free poses seeing each
/// >= n^3 / 20). ORB-SLAM-style windows are covisible by construction, so most reduced systems are
/// nearly full; only long chains of keyframes that each share points with a few neighbours go to
/// Ceres' sparse Schur.
bool prefersDenseSchur(const BundleProblem& problem);

/// Solves in place; returns per-observation outlier flags (chi-square test after the first pass
/// and again at the end, or point behind the camera).
std::vector<char> solveBundle(BundleProblem& problem, const PinholeIntrinsics& K, const BundleOptions& options);

}  // namespace tkgslam::optimize
