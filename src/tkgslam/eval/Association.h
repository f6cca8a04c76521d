#pragma once
// Timestamp association exactly as the TUM benchmark's associate.py: candidate pairs with
// |a - b| < max_difference (strict), taken greedily by smallest difference (ties broken by the
// smaller first stamp, then the smaller second stamp), each stamp used at most once.
#include <utility>
#include <vector>

namespace tkgslam::eval {

/// Returns index pairs (i into `first`, j into `second`), sorted by first stamp.
/// Both inputs must be sorted ascending.
std::vector<std::pair<int, int>> associateTimestamps(const std::vector<double>& first,
                                                     const std::vector<double>& second,
                                                     double max_difference = 0.02);

/// Index of the stamp closest to t, found with the same binary search as the TUM RPE script
/// (which keeps the first-probed element on ties). `stamps` must be sorted and non-empty.
int findClosestIndex(const std::vector<double>& stamps, double t);

}  // namespace tkgslam::eval
