#pragma once
// Levenberg-Marquardt on a bundle problem whose reduced camera system (the free poses, once the
// points are eliminated) is solved as a dense matrix: the covisible windows local mapping builds
// (prefersDenseSchur). Our own because Ceres spends most of such a solve outside the arithmetic:
// building and preprocessing the problem twice per BA, an independent-set ordering, virtual
// residual calls and a locked cell lookup per 6 x 6 block update.
//
// The same model as the Ceres path: residual sqrt(information) * (observed - predicted) pixels
// (u, v, u_right; u_right 0 without depth), optional Huber loss, cost 1/2 sum rho(|r|^2), and
// Ceres' Levenberg-Marquardt schedule (trust region 1e4, step accepted when it gives > 1e-3 of the
// predicted decrease, damping diag(J^T J) / radius). Poses are updated on the left, T_cw <-
// (exp(dtheta) R, t + dt); points additively (world, metres).
#include <vector>

#include "tkgslam/optimize/LocalBundleAdjuster.h"

namespace tkgslam::optimize {

struct DenseSchurSettings {
  int iterations = 10;      ///< LM iterations, rejected steps included (as Ceres counts them)
  bool robust = false;      ///< Huber loss with the thresholds below (on |r|, i.e. sqrt of chi-square)
  double huber_mono = 0;    ///< threshold for observations without depth
  double huber_stereo = 0;  ///< with depth
};

struct DenseSchurSummary {
  int iterations = 0;       ///< attempted steps
  int accepted = 0;
  double initial_cost = 0;  ///< 1/2 sum rho(|r|^2)
  double final_cost = 0;
};

/// Minimises over the free poses and the points of `problem` in place, leaving out the observations
/// with `excluded[k]` != 0 (size = observations, or empty for none).
DenseSchurSummary solveDenseSchur(BundleProblem& problem, const std::vector<char>& excluded,
                                  const PinholeIntrinsics& K, const DenseSchurSettings& settings);

}  // namespace tkgslam::optimize
