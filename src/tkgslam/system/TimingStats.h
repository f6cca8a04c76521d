#pragma once
// Per-frame timings of named pipeline stages, in milliseconds, with mean/median summaries.
#include <map>
#include <string>
#include <vector>

namespace tkgslam {

class TimingStats {
 public:
  void add(const std::string& stage, double ms) { samples_[stage].push_back(ms); }
  double mean(const std::string& stage) const;
  double median(const std::string& stage) const;
  size_t count(const std::string& stage) const;
  /// JSON object: { stage: {count, mean_ms, median_ms, p90_ms, max_ms}, ... }
  std::string toJson() const;
  const std::map<std::string, std::vector<double>>& samples() const { return samples_; }

 private:
  std::map<std::string, std::vector<double>> samples_;
};

}  // namespace tkgslam
