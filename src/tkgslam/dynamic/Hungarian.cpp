#include "tkgslam/dynamic/Hungarian.h"

#include <algorithm>
#include <limits>

namespace tkgslam::dynamic {

std::vector<int> solveAssignment(const std::vector<std::vector<double>>& cost) {
  const int n_rows = int(cost.size());
  if (n_rows == 0) return {};
  const int n_cols = int(cost[0].size());
  if (n_cols == 0) return std::vector<int>(n_rows, -1);
  // Work on a problem with rows <= columns (transpose if needed).
  const bool transposed = n_rows > n_cols;
  const int n = transposed ? n_cols : n_rows, m = transposed ? n_rows : n_cols;
  auto c = [&](int i, int j) { return transposed ? cost[j - 1][i - 1] : cost[i - 1][j - 1]; };
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> u(n + 1, 0), v(m + 1, 0);
  std::vector<int> p(m + 1, 0), way(m + 1, 0);  // p[j]: row matched to column j (1-based)
  for (int i = 1; i <= n; ++i) {
    p[0] = i;
    int j0 = 0;
    std::vector<double> minv(m + 1, inf);
    std::vector<char> used(m + 1, 0);
    do {
      used[j0] = 1;
      const int i0 = p[j0];
      double delta = inf;
      int j1 = 0;
      for (int j = 1; j <= m; ++j) {
        if (used[j]) continue;
        const double cur = c(i0, j) - u[i0] - v[j];
        if (cur < minv[j]) {
          minv[j] = cur;
          way[j] = j0;
        }
        if (minv[j] < delta) {
          delta = minv[j];
          j1 = j;
        }
      }
      for (int j = 0; j <= m; ++j) {
        if (used[j]) {
          u[p[j]] += delta;
          v[j] -= delta;
        } else {
          minv[j] -= delta;
        }
      }
      j0 = j1;
    } while (p[j0] != 0);
    do {
      const int j1 = way[j0];
      p[j0] = p[j1];
      j0 = j1;
    } while (j0);
  }
  std::vector<int> result(n_rows, -1);
  for (int j = 1; j <= m; ++j) {
    if (p[j] == 0) continue;
    if (transposed) result[j - 1] = p[j] - 1;
    else result[p[j] - 1] = j - 1;
  }
  return result;
}

}  // namespace tkgslam::dynamic
