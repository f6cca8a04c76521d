#include <random>

#include <ceres/autodiff_cost_function.h>
#include <gtest/gtest.h>

#include "tkgslam/optimize/ReprojectionCost.h"

namespace tkgslam {
namespace {

// The projection as the local BA wrote it for automatic differentiation before it had analytic
// Jacobians: the reference the analytic ones must agree with.
struct AutoDiffReprojection {
  optimize::BundleObservation o;
  optimize::PinholeIntrinsics K;

  template <typename T>
  bool operator()(const T* q, const T* t, const T* p, T* r) const {
    const Eigen::Matrix<T, 3, 1> pc = Eigen::Map<const Eigen::Quaternion<T>>(q) * Eigen::Map<const Eigen::Matrix<T, 3, 1>>(p) +
                                      Eigen::Map<const Eigen::Matrix<T, 3, 1>>(t);
    const T iz = T(1.0) / pc.z();
    const T u = T(K.fx) * pc.x() * iz + T(K.cx);
    const T v = T(K.fy) * pc.y() * iz + T(K.cy);
    const T s(std::sqrt(o.information));
    r[0] = s * (T(o.uv.x()) - u);
    r[1] = s * (T(o.uv.y()) - v);
    r[2] = o.u_right >= 0 ? s * (T(o.u_right) - (u - T(K.bf) * iz)) : T(0.0);
    return true;
  }
};

// Random cameras (quaternions also off unit length, as Ceres may evaluate between manifold steps),
// points 0.5-4 m in front, monocular and stereo observations with any information: residuals and
// all three Jacobians equal automatic differentiation's to 1e-9 relative.
TEST(ReprojectionCost, ResidualAndJacobiansEqualAutomaticDifferentiation) {
  const optimize::PinholeIntrinsics K{517.3, 516.5, 318.6, 255.3, 40.0};
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> U(-1, 1);
  int compared = 0;
  for (int trial = 0; trial < 200; ++trial) {
    Eigen::Quaterniond q(Eigen::AngleAxisd(0.5 * U(rng), Vec3(U(rng), U(rng), U(rng)).normalized()));
    q.coeffs() *= 1.0 + 0.05 * U(rng);
    const Vec3 t(0.3 * U(rng), 0.3 * U(rng), 0.3 * U(rng));
    const Vec3 pc(1.5 * U(rng), 1.2 * U(rng), 2.25 + 1.75 * U(rng));
    const Vec3 p = q.normalized().inverse() * (pc - t);
    optimize::BundleObservation o;
    o.uv = Vec2(320 + 300 * U(rng), 240 + 200 * U(rng));
    o.u_right = trial % 3 == 0 ? -1 : o.uv.x() - 20 - 10 * U(rng);
    o.information = 1.0 / std::pow(1.2, 2 * (trial % 8));

    const optimize::ReprojectionCost analytic(o, K);
    ceres::AutoDiffCostFunction<AutoDiffReprojection, 3, 4, 3, 3> automatic(new AutoDiffReprojection{o, K});
    const double* params[3] = {q.coeffs().data(), t.data(), p.data()};
    double r_a[3], r_b[3], jq_a[12], jt_a[9], jp_a[9], jq_b[12], jt_b[9], jp_b[9];
    double* j_a[3] = {jq_a, jt_a, jp_a};
    double* j_b[3] = {jq_b, jt_b, jp_b};
    ASSERT_TRUE(analytic.Evaluate(params, r_a, j_a));
    ASSERT_TRUE(automatic.Evaluate(params, r_b, j_b));
    for (int i = 0; i < 3; ++i) EXPECT_DOUBLE_EQ(r_a[i], r_b[i]) << "trial " << trial << " row " << i;
    auto expectNear = [&](const double* a, const double* b, int n, const char* what) {
      for (int i = 0; i < n; ++i) {
        EXPECT_NEAR(a[i], b[i], 1e-9 * (1 + std::abs(b[i]))) << what << " trial " << trial << " entry " << i;
        ++compared;
      }
    };
    expectNear(jq_a, jq_b, 12, "d/dq");
    expectNear(jt_a, jt_b, 9, "d/dt");
    expectNear(jp_a, jp_b, 9, "d/dp");
    if (o.u_right < 0) {
      for (int i = 0; i < 4; ++i) EXPECT_EQ(jq_a[8 + i], 0.0);  // no depth: the third row is 0
    }

    // The residual alone (the outlier test's chi-square) is the same numbers.
    double r_c[3];
    analytic.residualAt(q * p + t, r_c);
    for (int i = 0; i < 3; ++i) EXPECT_EQ(r_c[i], r_a[i]);

    // Jacobians may be asked for one block at a time.
    double jp_only[9];
    double* j_c[3] = {nullptr, nullptr, jp_only};
    ASSERT_TRUE(analytic.Evaluate(params, r_c, j_c));
    for (int i = 0; i < 9; ++i) EXPECT_EQ(jp_only[i], jp_a[i]);
  }
  EXPECT_EQ(compared, 200 * 30);
}

}  // namespace
}  // namespace tkgslam
