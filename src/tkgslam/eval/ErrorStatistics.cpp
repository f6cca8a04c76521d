#include "tkgslam/eval/ErrorStatistics.h"

#include <algorithm>
#include <cmath>

namespace tkgslam::eval {

ErrorStatistics ErrorStatistics::compute(const std::vector<double>& errors) {
  ErrorStatistics s;
  s.count = static_cast<int>(errors.size());
  if (errors.empty()) return s;
  double sum = 0, sum_sq = 0;
  for (double e : errors) {
    sum += e;
    sum_sq += e * e;
  }
  const double n = static_cast<double>(errors.size());
  s.rmse = std::sqrt(sum_sq / n);
  s.mean = sum / n;
  double var = 0;
  for (double e : errors) var += (e - s.mean) * (e - s.mean);
  s.std = std::sqrt(var / n);
  std::vector<double> sorted = errors;
  std::sort(sorted.begin(), sorted.end());
  const size_t m = sorted.size() / 2;
  s.median = sorted.size() % 2 ? sorted[m] : 0.5 * (sorted[m - 1] + sorted[m]);
  s.min = sorted.front();
  s.max = sorted.back();
  return s;
}

}  // namespace tkgslam::eval
