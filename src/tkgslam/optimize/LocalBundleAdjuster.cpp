#include "tkgslam/optimize/LocalBundleAdjuster.h"

#include <algorithm>
#include <cmath>

#include <ceres/ceres.h>

#include "tkgslam/optimize/DenseSchurSolver.h"
#include "tkgslam/optimize/ReprojectionCost.h"

namespace tkgslam::optimize {

namespace {

// When the reduced camera system is solved as a dense matrix (our solveDenseSchur) rather than
// sparse (Ceres' SPARSE_SCHUR with CHOLMOD). Eliminating the points costs about the same either
// way in arithmetic, but the sparse path pays a locked cell lookup per block update (work ~ sum
// over points of k^2, k = free poses seeing the point), the dense path a Cholesky factorisation of
// 6n x 6n (~ n^3). Refitted in session 54 on synthetic chains (n free poses, 20 points per
// keyframe, each seen by the keyframes within a band; one whole local BA, fastest of 3, dense vs
// sparse; sum k^2 / n^3 after n):
//   n = 296, 0.064:  2469 vs 2900 ms        n = 196, 0.084:  1008 vs 1987 ms
//   n = 396, 0.036:  7175 vs 6343 ms        n = 296, 0.027:  2924 vs 2712 ms
//   n = 196, 0.025:   847 vs  820 ms        n = 196, 0.013:   692 vs  495 ms
//   n = 296, 0.011:  2797 vs 1372 ms        n = 396, 0.010:  7536 vs 2863 ms
// (With Ceres' own dense Schur, session 50, the crossover was at 0.1.)
constexpr size_t kAlwaysDenseSchurPoses = 40;
constexpr size_t kMaxDenseSchurPoses = 400;  // 2400 x 2400 doubles: 46 MB
constexpr double kMinDenseSchurWorkPerCube = 0.05;

// The residual's squared norm: information x squared pixel error (the third row is 0 without depth).
double chi2Of(const BundleObservation& o, const PinholeIntrinsics& K, const Mat3& R, const Vec3& t,
              const Vec3& p, bool& behind) {
  const Vec3 pc = R * p + t;
  behind = pc.z() <= 0;
  if (behind) return 1e30;
  double r[3];
  ReprojectionCost(o, K).residualAt(pc, r);
  return r[0] * r[0] + r[1] * r[1] + r[2] * r[2];
}

// Large sparse reduced systems: Ceres with CHOLMOD (SPARSE_SCHUR). The poses go through Ceres'
// quaternion parametrisation and come back normalised.
void solveSparseSchur(BundleProblem& pb, const std::vector<char>& outlier, const PinholeIntrinsics& K, int iterations,
                      bool robust, const BundleOptions& opt) {
  const size_t nc = pb.poses.size();
  std::vector<Eigen::Quaterniond> q(nc);
  std::vector<Vec3> t(nc);
  for (size_t i = 0; i < nc; ++i) {
    q[i] = Eigen::Quaterniond(pb.poses[i].linear());
    q[i].normalize();
    t[i] = pb.poses[i].translation();
  }
  ceres::Problem::Options popts;
  popts.loss_function_ownership = ceres::TAKE_OWNERSHIP;
  ceres::Problem problem(popts);
  std::vector<char> pose_added(nc, 0);
  for (size_t k = 0; k < pb.observations.size(); ++k) {
    if (outlier[k]) continue;
    const auto& o = pb.observations[k];
    const bool stereo = o.u_right >= 0;
    ceres::CostFunction* cost = new ReprojectionCost(o, K);
    ceres::LossFunction* loss = robust ? new ceres::HuberLoss(std::sqrt(stereo ? opt.chi2_stereo : opt.chi2_mono)) : nullptr;
    problem.AddResidualBlock(cost, loss, q[o.camera].coeffs().data(), t[o.camera].data(), pb.points[o.point].data());
    if (!pose_added[o.camera]) {
      pose_added[o.camera] = 1;
      problem.SetManifold(q[o.camera].coeffs().data(), new ceres::EigenQuaternionManifold);
      if (pb.fixed_pose[o.camera]) {
        problem.SetParameterBlockConstant(q[o.camera].coeffs().data());
        problem.SetParameterBlockConstant(t[o.camera].data());
      }
    }
  }
  if (problem.NumResidualBlocks() == 0) return;
  ceres::Solver::Options so;
  so.linear_solver_type = ceres::SPARSE_SCHUR;
  so.max_num_iterations = iterations;
  so.num_threads = opt.threads;
  so.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(so, &problem, &summary);
  for (size_t i = 0; i < nc; ++i) {
    if (!pose_added[i] || pb.fixed_pose[i]) continue;
    pb.poses[i].linear() = q[i].normalized().toRotationMatrix();
    pb.poses[i].translation() = t[i];
  }
}

}  // namespace

bool prefersDenseSchur(const BundleProblem& pb) {
  const auto n = size_t(std::count(pb.fixed_pose.begin(), pb.fixed_pose.end(), 0));
  if (n <= kAlwaysDenseSchurPoses) return true;
  if (n > kMaxDenseSchurPoses) return false;
  std::vector<double> free_seen(pb.points.size(), 0.0);
  for (const auto& o : pb.observations)
    if (!pb.fixed_pose[size_t(o.camera)]) free_seen[size_t(o.point)] += 1;
  double work = 0;
  for (const double k : free_seen) work += k * k;
  return work >= kMinDenseSchurWorkPerCube * double(n) * double(n) * double(n);
}

std::vector<char> solveBundle(BundleProblem& pb, const PinholeIntrinsics& K, const BundleOptions& opt) {
  std::vector<char> outlier(pb.observations.size(), 0);
  auto classify = [&] {
    for (size_t k = 0; k < pb.observations.size(); ++k) {
      const auto& o = pb.observations[k];
      const Pose& T = pb.poses[size_t(o.camera)];
      bool behind = false;
      const double chi2 = chi2Of(o, K, T.linear(), T.translation(), pb.points[size_t(o.point)], behind);
      outlier[k] = behind || chi2 > (o.u_right >= 0 ? opt.chi2_stereo : opt.chi2_mono);
    }
  };
  const bool dense_schur = prefersDenseSchur(pb);
  auto run = [&](int iterations, bool robust) {
    if (dense_schur) {
      DenseSchurSettings settings;
      settings.iterations = iterations;
      settings.robust = robust;
      settings.huber_mono = std::sqrt(opt.chi2_mono);
      settings.huber_stereo = std::sqrt(opt.chi2_stereo);
      solveDenseSchur(pb, outlier, K, settings);
    } else {
      solveSparseSchur(pb, outlier, K, iterations, robust, opt);
    }
  };
  run(opt.iterations_first, true);
  classify();
  if (opt.iterations_second > 0) {
    run(opt.iterations_second, false);
    classify();
  }
  return outlier;
}

}  // namespace tkgslam::optimize
