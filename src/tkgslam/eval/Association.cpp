#include "tkgslam/eval/Association.h"

#include <algorithm>
#include <cmath>
#include <tuple>

namespace tkgslam::eval {

std::vector<std::pair<int, int>> associateTimestamps(const std::vector<double>& first,
                                                     const std::vector<double>& second,
                                                     double max_difference) {
  // Candidates: for each a, the b's within the window (both lists sorted -> two pointers).
  std::vector<std::tuple<double, double, double, int, int>> candidates;  // diff, a, b, i, j
  size_t lo = 0;
  for (size_t i = 0; i < first.size(); ++i) {
    const double a = first[i];
    while (lo < second.size() && second[lo] <= a - max_difference) ++lo;
    for (size_t j = lo; j < second.size() && second[j] < a + max_difference; ++j) {
      const double diff = std::abs(a - second[j]);
      if (diff < max_difference) candidates.emplace_back(diff, a, second[j], int(i), int(j));
    }
  }
  std::sort(candidates.begin(), candidates.end());
  std::vector<char> used_a(first.size(), 0), used_b(second.size(), 0);
  std::vector<std::pair<int, int>> matches;
  for (const auto& c : candidates) {
    const int i = std::get<3>(c), j = std::get<4>(c);
    if (used_a[i] || used_b[j]) continue;
    used_a[i] = used_b[j] = 1;
    matches.emplace_back(i, j);
  }
  std::sort(matches.begin(), matches.end());
  return matches;
}

int findClosestIndex(const std::vector<double>& stamps, double t) {
  int beginning = 0;
  int end = static_cast<int>(stamps.size());
  double difference = std::abs(stamps[0] - t);
  int best = 0;
  while (beginning < end) {
    const int middle = (end + beginning) / 2;
    if (std::abs(stamps[middle] - t) < difference) {
      difference = std::abs(stamps[middle] - t);
      best = middle;
    }
    if (t == stamps[middle]) return middle;
    if (stamps[middle] > t) {
      end = middle;
    } else {
      beginning = middle + 1;
    }
  }
  return best;
}

}  // namespace tkgslam::eval
