#pragma once
// The bundle adjustment's reprojection residual with analytic Jacobians. Parameters: the camera's
// rotation as an Eigen quaternion (x, y, z, w; world to camera, on Ceres' EigenQuaternionManifold),
// its translation t (T_cw, metres) and the world point (metres). Residual = sqrt(information) *
// (observed - predicted) in pixels: (u, v, u_right), the third 0 for an observation without depth.
// Every residual has 3 rows (and every block 3 tangent dimensions) so Ceres uses its fixed-size
// Schur eliminator <3, 3, 3>. Same values and derivatives as automatic differentiation of the
// projection (to rounding; test ReprojectionCost.*), with 26 % fewer instructions in Ceres'
// residual evaluation and 7 % fewer in the whole local BA (callgrind, BM_LocalBundleAdjustment).
#include <ceres/sized_cost_function.h>

#include "tkgslam/optimize/LocalBundleAdjuster.h"

namespace tkgslam::optimize {

class ReprojectionCost final : public ceres::SizedCostFunction<3, 4, 3, 3> {
 public:
  ReprojectionCost(const BundleObservation& observation, const PinholeIntrinsics& K);

  /// parameters: {q (4), t (3), p_w (3)}; jacobians row-major, each may be null.
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override;

  /// Residual alone (no Ceres) of the point in camera coordinates (p_c = q p_w + t, metres): its
  /// squared norm is the observation's chi-square.
  void residualAt(const Vec3& p_c, double* r) const;

 private:
  Vec2 uv_;
  double u_right_;  ///< < 0: no depth, third residual 0
  PinholeIntrinsics K_;
  double s_;  ///< sqrt(information)
};

}  // namespace tkgslam::optimize
