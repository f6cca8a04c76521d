#pragma once
// A synthetic local-BA problem like the ones local mapping builds: keyframes along a short path
// looking at random points 0.5-3 m away, two of them held fixed, a third of the observations
// without depth (monocular residuals), pixel noise, and a share of gross outliers. Shared by the
// bundle-adjustment test and its benchmark.
#include <cstdlib>
#include <random>
#include <vector>

#include "tkgslam/optimize/LocalBundleAdjuster.h"

namespace tkgslam::test {

struct SyntheticBundle {
  optimize::PinholeIntrinsics K{517.3, 516.5, 318.6, 255.3, 40.0};
  optimize::BundleProblem problem;   ///< perturbed start
  std::vector<Pose> true_poses;      ///< T_cw
  std::vector<Vec3> true_points;
  std::vector<char> is_outlier;      ///< per observation
};

/// `outlier_share` of the observations are moved 40-100 px; the free poses start 1 cm / 0.3 degrees
/// off (a tracked keyframe's error) and the points 3 cm off.
/// The keyframes are `spacing` metres and `turn` radians apart; u, v and u_right have independent
/// 0.1 px noise (the residuals' model: one sigma for all three). With `band` < 0 every keyframe sees
/// every point (in front of the first keyframe); otherwise point p lies in front of keyframe
/// p % cameras and only the keyframes within `band` of that one see it: a long chain in which each
/// keyframe shares points with a few neighbours only.
inline SyntheticBundle makeSyntheticBundle(int cameras, int points, double outlier_share, double spacing = 0.05,
                                           double turn = 0.02, int band = -1, unsigned seed = 5) {
  SyntheticBundle s;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> ux(-1.0, 1.0), uz(0.5, 3.0), u01(0, 1);
  std::normal_distribution<double> pixel(0.0, 0.1), step(0.0, 1.0);
  const auto direction = [&] { return Vec3(step(rng), step(rng), step(rng)).normalized(); };
  for (int c = 0; c < cameras; ++c) {
    Pose T = Pose::Identity();
    T.linear() = Eigen::AngleAxisd(turn * c, Vec3(0.1, 1, 0.2).normalized()).toRotationMatrix();
    T.translation() = spacing * c * Vec3(1.0, -0.2, 0.4);
    s.true_poses.push_back(T);
    Pose start = T;
    if (c >= 2) {
      start.linear() = expSO3(0.005 * direction()) * T.linear();
      start.translation() += 0.01 * direction();
    }
    s.problem.poses.push_back(start);
    s.problem.fixed_pose.push_back(c < 2);
  }
  for (int p = 0; p < points; ++p) {
    const Vec3 pc(ux(rng), ux(rng) * 0.7, uz(rng));
    const int anchor = band < 0 ? 0 : p % cameras;
    const Vec3 pw = s.true_poses[size_t(anchor)].inverse() * pc;
    s.true_points.push_back(pw);
    s.problem.points.push_back(pw + 0.03 * direction());
    for (int c = 0; c < cameras; ++c) {
      if (band >= 0 && std::abs(c - anchor) > band) continue;
      const Vec3 q = s.true_poses[size_t(c)] * pw;
      optimize::BundleObservation o;
      o.camera = c;
      o.point = p;
      const double u = s.K.fx * q.x() / q.z() + s.K.cx, v = s.K.fy * q.y() / q.z() + s.K.cy;
      o.uv = Vec2(u + pixel(rng), v + pixel(rng));
      o.u_right = (p + c) % 3 == 0 ? -1.0 : u - s.K.bf / q.z() + pixel(rng);
      const bool outlier = u01(rng) < outlier_share;
      if (outlier) {
        o.uv += Vec2(40 + 60 * u01(rng), -40 - 60 * u01(rng));
        if (o.u_right >= 0) o.u_right = o.uv.x() - 25;
      }
      s.problem.observations.push_back(o);
      s.is_outlier.push_back(outlier);
    }
  }
  return s;
}

}  // namespace tkgslam::test
