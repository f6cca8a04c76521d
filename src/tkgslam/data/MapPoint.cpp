#include "tkgslam/data/MapPoint.h"

#include <algorithm>
#include <cmath>

#include "tkgslam/data/KeyFrame.h"

namespace tkgslam::data {

bool KeyFrameIdLess::operator()(const KeyFrame* a, const KeyFrame* b) const { return a->id < b->id; }

MapPoint::MapPoint(long id_, const Vec3& pos, KeyFrame* ref, const cv::Mat& desc)
    : id(id_), pos_w(pos), descriptor(desc.clone()), reference(ref), first_keyframe_id(ref ? ref->id : 0) {}

int MapPoint::observationWeight() const {
  int n = 0;
  for (const auto& [kf, idx] : observations) n += kf->features->u_right[idx] >= 0 ? 2 : 1;
  return n;
}

int MapPoint::predictScale(double dist, const feature::ScalePyramid& pyr) const {
  const double ratio = max_distance / dist;
  int level = int(std::ceil(std::log(ratio) / pyr.log_scale_factor));
  return std::clamp(level, 0, pyr.levels - 1);
}

void MapPoint::updateNormalAndDepth(const feature::ScalePyramid& pyr) {
  if (bad || observations.empty() || !reference) return;
  Vec3 n = Vec3::Zero();
  int count = 0;
  for (const auto& [kf, idx] : observations) {
    n += (pos_w - kf->centre()).normalized();
    ++count;
  }
  normal = (n / count).normalized();
  auto it = observations.find(reference);
  if (it == observations.end()) return;
  const double dist = (pos_w - reference->centre()).norm();
  const int level = reference->features->ideal[it->second].octave;
  max_distance = float(dist * pyr.scales[level]);
  min_distance = float(max_distance / pyr.scales[pyr.levels - 1]);
}

void MapPoint::computeDistinctiveDescriptor() {
  if (bad || observations.empty()) return;
  std::vector<cv::Mat> descs;
  descs.reserve(observations.size());
  for (const auto& [kf, idx] : observations) descs.push_back(kf->features->descriptors.row(idx));
  const size_t n = descs.size();
  std::vector<std::vector<int>> dist(n, std::vector<int>(n, 0));
  for (size_t i = 0; i < n; ++i) {
    for (size_t j = i + 1; j < n; ++j) dist[i][j] = dist[j][i] = descriptorDistance(descs[i], descs[j]);
  }
  int best_median = 257;
  size_t best = 0;
  for (size_t i = 0; i < n; ++i) {
    std::vector<int> d = dist[i];
    std::nth_element(d.begin(), d.begin() + (n - 1) / 2, d.end());
    const int median = d[(n - 1) / 2];
    if (median < best_median) {
      best_median = median;
      best = i;
    }
  }
  descriptor = descs[best].clone();
}

}  // namespace tkgslam::data
