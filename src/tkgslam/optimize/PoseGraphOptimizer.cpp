#include "tkgslam/optimize/PoseGraphOptimizer.h"

#include <cmath>

#include <ceres/ceres.h>

namespace tkgslam::optimize {

namespace {

// Residual of one edge: the error pose E = T_ij^-1 * T_i * T_j^-1 (identity when the two poses
// agree with the measurement) as (2 * quaternion vector part ~ rotation vector, translation).
struct RelativePoseError {
  RelativePoseError(const Pose& T_ij, double weight)
      : q_ji(Eigen::Quaterniond(T_ij.linear()).conjugate()), t_ji(-(q_ji * T_ij.translation())), s(std::sqrt(weight)) {}

  template <typename T>
  bool operator()(const T* qi_p, const T* ti_p, const T* qj_p, const T* tj_p, T* r) const {
    Eigen::Map<const Eigen::Quaternion<T>> qi(qi_p), qj(qj_p);
    Eigen::Map<const Eigen::Matrix<T, 3, 1>> ti(ti_p), tj(tj_p);
    // T_i * T_j^-1
    const Eigen::Quaternion<T> qj_inv = qj.conjugate();
    const Eigen::Quaternion<T> q_rel = qi * qj_inv;
    const Eigen::Matrix<T, 3, 1> t_rel = ti - q_rel * tj;
    // T_ij^-1 * (T_i * T_j^-1)
    const Eigen::Quaternion<T> q_meas = q_ji.cast<T>();
    const Eigen::Quaternion<T> q_err = q_meas * q_rel;
    const Eigen::Matrix<T, 3, 1> t_err = q_meas * t_rel + t_ji.cast<T>();
    // q and -q are the same rotation: take the one with w >= 0.
    const T sign = q_err.w() < T(0) ? T(-1) : T(1);
    for (int k = 0; k < 3; ++k) {
      r[k] = T(2 * s) * sign * q_err.vec()[k];
      r[3 + k] = T(s) * t_err[k];
    }
    return true;
  }

  Eigen::Quaterniond q_ji;
  Eigen::Vector3d t_ji;
  double s;
};

}  // namespace

bool optimizePoseGraph(PoseGraph& graph, const PoseGraphOptions& options) {
  const size_t n = graph.poses.size();
  std::vector<Eigen::Quaterniond> q(n);
  std::vector<Eigen::Vector3d> t(n);
  for (size_t k = 0; k < n; ++k) {
    q[k] = Eigen::Quaterniond(graph.poses[k].linear()).normalized();
    t[k] = graph.poses[k].translation();
  }
  ceres::Problem problem;
  for (const auto& e : graph.edges) {
    auto* cost = new ceres::AutoDiffCostFunction<RelativePoseError, 6, 4, 3, 4, 3>(new RelativePoseError(e.T_ij, e.weight));
    problem.AddResidualBlock(cost, nullptr, q[e.i].coeffs().data(), t[e.i].data(), q[e.j].coeffs().data(),
                             t[e.j].data());
  }
  bool any_fixed = false;
  for (size_t k = 0; k < n; ++k) {
    if (!problem.HasParameterBlock(q[k].coeffs().data())) continue;
    problem.SetManifold(q[k].coeffs().data(), new ceres::EigenQuaternionManifold);
    if (graph.fixed[k]) {
      problem.SetParameterBlockConstant(q[k].coeffs().data());
      problem.SetParameterBlockConstant(t[k].data());
      any_fixed = true;
    }
  }
  if (!any_fixed) return false;
  ceres::Solver::Options opts;
  opts.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  opts.max_num_iterations = options.iterations;
  opts.num_threads = options.threads;
  opts.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(opts, &problem, &summary);
  if (!summary.IsSolutionUsable()) return false;
  for (size_t k = 0; k < n; ++k) {
    Pose T = Pose::Identity();
    T.linear() = q[k].normalized().toRotationMatrix();
    T.translation() = t[k];
    graph.poses[k] = T;
  }
  return true;
}

}  // namespace tkgslam::optimize
