#pragma once
// Summary statistics of a set of errors, computed as numpy does in the TUM scripts
// (population standard deviation, median averaging the two middle values).
#include <vector>

namespace tkgslam::eval {

struct ErrorStatistics {
  int count = 0;
  double rmse = 0, mean = 0, median = 0, std = 0, min = 0, max = 0;

  static ErrorStatistics compute(const std::vector<double>& errors);
};

}  // namespace tkgslam::eval
