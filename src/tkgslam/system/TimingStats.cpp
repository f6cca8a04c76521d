#include "tkgslam/system/TimingStats.h"

#include <algorithm>
#include <numeric>

#include <fmt/format.h>

namespace tkgslam {

namespace {
double quantile(std::vector<double> v, double q) {
  if (v.empty()) return 0;
  const size_t k = std::min(v.size() - 1, size_t(q * double(v.size() - 1) + 0.5));
  std::nth_element(v.begin(), v.begin() + k, v.end());
  return v[k];
}
}  // namespace

double TimingStats::mean(const std::string& stage) const {
  auto it = samples_.find(stage);
  if (it == samples_.end() || it->second.empty()) return 0;
  return std::accumulate(it->second.begin(), it->second.end(), 0.0) / double(it->second.size());
}

double TimingStats::median(const std::string& stage) const {
  auto it = samples_.find(stage);
  return it == samples_.end() ? 0 : quantile(it->second, 0.5);
}

size_t TimingStats::count(const std::string& stage) const {
  auto it = samples_.find(stage);
  return it == samples_.end() ? 0 : it->second.size();
}

std::string TimingStats::toJson() const {
  std::string s = "{";
  bool first = true;
  for (const auto& [stage, v] : samples_) {
    s += fmt::format("{}\n  \"{}\": {{\"count\": {}, \"mean_ms\": {:.3f}, \"median_ms\": {:.3f}, \"p90_ms\": {:.3f}, "
                     "\"max_ms\": {:.3f}}}",
                     first ? "" : ",", stage, v.size(), mean(stage), quantile(v, 0.5), quantile(v, 0.9),
                     v.empty() ? 0.0 : *std::max_element(v.begin(), v.end()));
    first = false;
  }
  return s + "\n}";
}

}  // namespace tkgslam
