#pragma once
// SE(3) pose-graph optimisation (ORB-SLAM2's essential-graph step after a loop, without scale:
// RGB-D has metric depth). Nodes are world -> camera poses; an edge holds a measured relative
// pose between two of them. Used to spread a loop-closure correction over the keyframes.
#include <vector>

#include "tkgslam/common/Pose.h"

namespace tkgslam::optimize {

struct PoseGraphEdge {
  int i = 0, j = 0;  ///< node indices
  /// Measured T_ij = T_i_cw * T_j_cw^-1 (camera j -> camera i).
  Pose T_ij = Pose::Identity();
  /// Scales the squared residual (rotation in rad, translation in m); e.g. shared map points.
  double weight = 1;
};

struct PoseGraph {
  std::vector<Pose> poses;  ///< T_cw per node; optimised in place
  std::vector<char> fixed;  ///< per node: held constant
  std::vector<PoseGraphEdge> edges;
};

struct PoseGraphOptions {
  int iterations = 20;
  int threads = 1;
};

/// Minimises sum over edges of weight * |r|^2, r = (2 vec(q), t) of T_ij^-1 * T_i * T_j^-1.
/// Needs at least one fixed node (gauge). Returns false if the solver failed (poses unchanged).
bool optimizePoseGraph(PoseGraph& graph, const PoseGraphOptions& options = {});

}  // namespace tkgslam::optimize
