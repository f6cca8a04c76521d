#pragma once
// Minimum-cost assignment (Hungarian / Kuhn-Munkres with potentials, O(n^2 m)).
#include <vector>

namespace tkgslam::dynamic {

/// cost[i][j] for rows i (n) and columns j (m), any n, m. Returns for each row the assigned
/// column, or -1 when there are more rows than columns. Minimises the total cost.
std::vector<int> solveAssignment(const std::vector<std::vector<double>>& cost);

}  // namespace tkgslam::dynamic
