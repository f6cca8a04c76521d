#include "tkgslam/optimize/DenseSchurSolver.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Cholesky>

namespace tkgslam::optimize {

namespace {

using Mat6 = Eigen::Matrix<double, 6, 6>;
using Vec6 = Eigen::Matrix<double, 6, 1>;
using Mat63 = Eigen::Matrix<double, 6, 3>;
using Mat36 = Eigen::Matrix<double, 3, 6>;

// Ceres' defaults for its Levenberg-Marquardt trust region.
constexpr double kInitialRadius = 1e4;
constexpr double kMaxRadius = 1e16;
constexpr double kMinRadius = 1e-32;
constexpr double kMinRelativeDecrease = 1e-3;
constexpr double kFunctionTolerance = 1e-6;
constexpr double kParameterTolerance = 1e-8;
constexpr double kMinDiagonal = 1e-6;
constexpr double kMaxDiagonal = 1e32;

struct Residual {
  int observation;
  int camera;  ///< index among the free cameras, -1 for a fixed one
  int point;   ///< index among the points in use
  double s;    ///< sqrt(information)
  double huber;
};

Vec3 clampedDiagonal3(const Mat3& m) { return m.diagonal().cwiseMax(kMinDiagonal).cwiseMin(kMaxDiagonal); }
Vec6 clampedDiagonal6(const Mat6& m) { return m.diagonal().cwiseMax(kMinDiagonal).cwiseMin(kMaxDiagonal); }

// rho(|r|^2) of Ceres' Huber loss (or the plain square) and its derivative, the IRLS weight.
double robustCost(double s2, double huber, double* weight) {
  if (huber <= 0 || s2 <= huber * huber) {
    *weight = 1;
    return s2;
  }
  const double norm = std::sqrt(s2);
  *weight = huber / norm;
  return 2 * huber * norm - huber * huber;
}

class Solver {
 public:
  Solver(BundleProblem& pb, const std::vector<char>& excluded, const PinholeIntrinsics& K,
         const DenseSchurSettings& st)
      : pb_(pb), K_(K), st_(st) {
    std::vector<int> camera_index(pb.poses.size(), -1), point_index(pb.points.size(), -1);
    for (size_t k = 0; k < pb.observations.size(); ++k) {
      if (!excluded.empty() && excluded[k]) continue;
      const auto& o = pb.observations[k];
      int& c = camera_index[size_t(o.camera)];
      if (c < 0 && !pb.fixed_pose[size_t(o.camera)]) {
        c = int(cameras_.size());
        cameras_.push_back(o.camera);
      }
      int& p = point_index[size_t(o.point)];
      if (p < 0) {
        p = int(points_.size());
        points_.push_back(o.point);
      }
      residuals_.push_back({int(k), c, p, std::sqrt(o.information),
                            st.robust ? (o.u_right >= 0 ? st.huber_stereo : st.huber_mono) : 0.0});
    }
    // Grouped by point (stable: the order within a point is the problem's) for the elimination.
    std::stable_sort(residuals_.begin(), residuals_.end(),
                     [](const Residual& a, const Residual& b) { return a.point < b.point; });
    point_begin_.assign(points_.size() + 1, 0);
    for (const auto& r : residuals_) ++point_begin_[size_t(r.point) + 1];
    for (size_t j = 0; j < points_.size(); ++j) point_begin_[j + 1] += point_begin_[j];
  }

  DenseSchurSummary run() {
    DenseSchurSummary summary;
    if (residuals_.empty()) return summary;
    double cost = costAt(pb_.poses, pb_.points);
    summary.initial_cost = summary.final_cost = cost;
    linearize();
    double radius = kInitialRadius, decrease = 2;
    std::vector<Pose> poses;
    std::vector<Vec3> points;
    while (summary.iterations < st_.iterations) {
      ++summary.iterations;
      double model_change = 0;
      const bool solved = solveStep(radius, &model_change);
      if (solved && stepIsNegligible()) break;
      bool accepted = false;
      double new_cost = 0;
      if (solved && model_change > 0) {
        poses = pb_.poses;
        points = pb_.points;
        applyStep(poses, points);
        new_cost = costAt(poses, points);
        accepted = std::isfinite(new_cost) && (cost - new_cost) / model_change > kMinRelativeDecrease;
      }
      if (!accepted) {
        radius /= decrease;
        decrease *= 2;
        if (radius < kMinRadius) break;
        continue;
      }
      const double quality = (cost - new_cost) / model_change;
      radius = std::min(kMaxRadius, radius / std::max(1.0 / 3.0, 1.0 - std::pow(2.0 * quality - 1.0, 3)));
      decrease = 2;
      pb_.poses.swap(poses);
      pb_.points.swap(points);
      ++summary.accepted;
      const double change = cost - new_cost;
      cost = new_cost;
      summary.final_cost = cost;
      if (std::abs(change) <= kFunctionTolerance * (cost + change)) break;
      linearize();
    }
    return summary;
  }

 private:
  double costAt(const std::vector<Pose>& poses, const std::vector<Vec3>& points) const {
    double sum = 0;
    for (const auto& r : residuals_) {
      const auto& o = pb_.observations[size_t(r.observation)];
      const Vec3 e = stereoResidual(K_, o.uv, o.u_right, r.s, poses[size_t(o.camera)] * points[size_t(o.point)]);
      double w;
      sum += robustCost(e.squaredNorm(), r.huber, &w);
    }
    return 0.5 * sum;
  }

  // Normal equations at the current estimate: U (camera blocks), V (point blocks), W (one 6 x 3
  // block per observation by a free camera) and the gradient J^T r, each weighted by the loss.
  void linearize() {
    U_.assign(cameras_.size(), Mat6::Zero());
    gc_.assign(cameras_.size(), Vec6::Zero());
    V_.assign(points_.size(), Mat3::Zero());
    gp_.assign(points_.size(), Vec3::Zero());
    W_.resize(residuals_.size());
    for (size_t k = 0; k < residuals_.size(); ++k) {
      const auto& r = residuals_[k];
      const auto& o = pb_.observations[size_t(r.observation)];
      const Pose& T = pb_.poses[size_t(o.camera)];
      const Vec3 rotated = T.linear() * pb_.points[size_t(o.point)];
      const Vec3 pc = rotated + T.translation();
      const Vec3 e = stereoResidual(K_, o.uv, o.u_right, r.s, pc);
      double w;
      robustCost(e.squaredNorm(), r.huber, &w);
      const Mat3 A = -r.s * projectStereoJacobian(K_, pc, o.u_right >= 0);  // d e / d p_c
      const Mat3 Jp = A * T.linear();
      V_[size_t(r.point)].noalias() += w * Jp.transpose() * Jp;
      gp_[size_t(r.point)].noalias() += w * Jp.transpose() * e;
      if (r.camera < 0) continue;
      Mat36 Jc;
      Jc.leftCols<3>() = -A * skew(rotated);  // d p_c / d dtheta = -[R p]x
      Jc.rightCols<3>() = A;
      U_[size_t(r.camera)].noalias() += w * Jc.transpose() * Jc;
      gc_[size_t(r.camera)].noalias() += w * Jc.transpose() * e;
      W_[k].noalias() = w * Jc.transpose() * Jp;
    }
  }

  // One damped step: points eliminated, the reduced camera system factorised densely, the points
  // back-substituted. False when a system is not positive definite.
  bool solveStep(double radius, double* model_change) {
    const long n = long(cameras_.size());
    S_.setZero(6 * n, 6 * n);
    Eigen::VectorXd rhs(6 * n);
    double damping = 0;  // delta^T D delta / radius, for the model's decrease
    Dc_.resize(size_t(n));
    for (long i = 0; i < n; ++i) {
      Dc_[size_t(i)] = clampedDiagonal6(U_[size_t(i)]);
      S_.block<6, 6>(6 * i, 6 * i) = U_[size_t(i)];
      S_.block<6, 6>(6 * i, 6 * i).diagonal() += Dc_[size_t(i)] / radius;
      rhs.segment<6>(6 * i) = -gc_[size_t(i)];
    }
    Vinv_.resize(points_.size());
    Dp_.resize(points_.size());
    std::vector<Mat36> Y;  // Vinv W^T per free observation of the point
    for (size_t j = 0; j < points_.size(); ++j) {
      Dp_[j] = clampedDiagonal3(V_[j]);
      Mat3 V = V_[j];
      V.diagonal() += Dp_[j] / radius;
      const Eigen::LLT<Mat3> llt(V);
      if (llt.info() != Eigen::Success) return false;
      Vinv_[j] = llt.solve(Mat3::Identity());
      const Vec3 vg = Vinv_[j] * gp_[j];
      const int begin = point_begin_[j], end = point_begin_[j + 1];
      Y.resize(size_t(end - begin));
      for (int a = begin; a < end; ++a) {
        const int ca = residuals_[size_t(a)].camera;
        if (ca < 0) continue;
        Y[size_t(a - begin)].noalias() = Vinv_[j] * W_[size_t(a)].transpose();
        rhs.segment<6>(6 * ca).noalias() += W_[size_t(a)] * vg;
        // S -= W_a Vinv W_b^T over the pairs, into the lower triangle.
        for (int b = begin; b <= a; ++b) {
          const int cb = residuals_[size_t(b)].camera;
          if (cb < 0) continue;
          if (ca > cb || (ca == cb && a == b)) {
            S_.block<6, 6>(6 * ca, 6 * cb).noalias() -= W_[size_t(a)] * Y[size_t(b - begin)];
          } else if (ca < cb) {
            S_.block<6, 6>(6 * cb, 6 * ca).noalias() -= W_[size_t(b)] * Y[size_t(a - begin)];
          } else {  // two observations of the point by one camera
            S_.block<6, 6>(6 * ca, 6 * ca).noalias() -=
                W_[size_t(a)] * Y[size_t(b - begin)] + W_[size_t(b)] * Y[size_t(a - begin)];
          }
        }
      }
    }
    Eigen::LLT<Eigen::Ref<Eigen::MatrixXd>, Eigen::Lower> llt(S_);
    if (llt.info() != Eigen::Success) return false;
    const Eigen::VectorXd dc = llt.solve(rhs);
    double gradient_step = 0;  // g^T delta
    dc_.resize(size_t(n));
    for (long i = 0; i < n; ++i) {
      dc_[size_t(i)] = dc.segment<6>(6 * i);
      gradient_step += gc_[size_t(i)].dot(dc_[size_t(i)]);
      damping += dc_[size_t(i)].cwiseAbs2().dot(Dc_[size_t(i)]) / radius;
    }
    dp_.resize(points_.size());
    for (size_t j = 0; j < points_.size(); ++j) {
      Vec3 b = -gp_[j];
      for (int a = point_begin_[j]; a < point_begin_[j + 1]; ++a) {
        const int ca = residuals_[size_t(a)].camera;
        if (ca >= 0) b.noalias() -= W_[size_t(a)].transpose() * dc_[size_t(ca)];
      }
      dp_[j] = Vinv_[j] * b;
      gradient_step += gp_[j].dot(dp_[j]);
      damping += dp_[j].cwiseAbs2().dot(Dp_[j]) / radius;
    }
    // 1/2 (|r|^2 - |r + J delta|^2) with (J^T J + D / radius) delta = -g.
    *model_change = 0.5 * (-gradient_step + damping);
    return std::isfinite(*model_change);
  }

  // Ceres' parameter tolerance: the step is negligible against the parameters.
  bool stepIsNegligible() const {
    double step = 0, x = 0;
    for (size_t i = 0; i < cameras_.size(); ++i) {
      step += dc_[i].squaredNorm();
      x += 1 + pb_.poses[size_t(cameras_[i])].translation().squaredNorm();  // a unit quaternion and t
    }
    for (size_t j = 0; j < points_.size(); ++j) {
      step += dp_[j].squaredNorm();
      x += pb_.points[size_t(points_[j])].squaredNorm();
    }
    return std::sqrt(step) <= kParameterTolerance * (std::sqrt(x) + kParameterTolerance);
  }

  void applyStep(std::vector<Pose>& poses, std::vector<Vec3>& points) const {
    for (size_t i = 0; i < cameras_.size(); ++i) {
      Pose& T = poses[size_t(cameras_[i])];
      const Eigen::Quaterniond q(expSO3(dc_[i].head<3>()) * T.linear());
      T.linear() = q.normalized().toRotationMatrix();
      T.translation() += dc_[i].tail<3>();
    }
    for (size_t j = 0; j < points_.size(); ++j) points[size_t(points_[j])] += dp_[j];
  }

  BundleProblem& pb_;
  const PinholeIntrinsics K_;
  const DenseSchurSettings st_;
  std::vector<int> cameras_;  ///< free camera index -> problem pose
  std::vector<int> points_;   ///< point index -> problem point
  std::vector<Residual> residuals_;
  std::vector<int> point_begin_;  ///< residuals_[point_begin_[j], point_begin_[j + 1]) observe point j
  std::vector<Mat6> U_;
  std::vector<Vec6> gc_;
  std::vector<Mat3> V_;
  std::vector<Vec3> gp_;
  std::vector<Mat63> W_;  ///< per residual (unused for fixed cameras)
  std::vector<Mat3> Vinv_;
  std::vector<Vec6> Dc_;  ///< the step's damping diagonals (clamped diag of U, V), before / radius
  std::vector<Vec3> Dp_;
  std::vector<Vec6> dc_;
  std::vector<Vec3> dp_;
  Eigen::MatrixXd S_;
};

}  // namespace

DenseSchurSummary solveDenseSchur(BundleProblem& problem, const std::vector<char>& excluded,
                                  const PinholeIntrinsics& K, const DenseSchurSettings& settings) {
  return Solver(problem, excluded, K, settings).run();
}

}  // namespace tkgslam::optimize
