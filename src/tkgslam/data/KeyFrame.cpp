#include "tkgslam/data/KeyFrame.h"

#include <algorithm>

namespace tkgslam::data {

KeyFrame::KeyFrame(long id_, long frame_id_, double timestamp_, std::shared_ptr<const FrameFeatures> f,
                   const Pose& T_cw)
    : id(id_), frame_id(frame_id_), timestamp(timestamp_), features(std::move(f)) {
  map_points.resize(features->size());
  setPose(T_cw);
}

void KeyFrame::sortConnections() {
  std::vector<std::pair<int, KeyFrame*>> v;
  for (const auto& [kf, w] : connections) v.emplace_back(w, kf);
  std::sort(v.begin(), v.end(), [](const auto& a, const auto& b) {
    return a.first != b.first ? a.first > b.first : a.second->id < b.second->id;
  });
  ordered_connections.clear();
  for (const auto& p : v) ordered_connections.push_back(p.second);
}

void KeyFrame::updateConnections() {
  std::map<KeyFrame*, int, KeyFrameIdLess> counter;
  for (const auto& mp : map_points) {
    if (!mp || mp->bad) continue;
    for (const auto& [kf, idx] : mp->observations) {
      if (kf != this && !kf->bad) counter[kf]++;
    }
  }
  // Old links that vanished are removed on both sides.
  for (auto& [kf, w] : connections) {
    if (!counter.count(kf)) kf->eraseConnection(this);
  }
  connections.clear();
  if (counter.empty()) {
    ordered_connections.clear();
    return;
  }
  constexpr int kMinWeight = 15;
  KeyFrame* best = nullptr;
  int best_w = 0;
  for (const auto& [kf, w] : counter) {
    if (w > best_w) {
      best_w = w;
      best = kf;
    }
    if (w >= kMinWeight) {
      connections[kf] = w;
      kf->connections[this] = w;
      kf->sortConnections();
    }
  }
  if (connections.empty()) {  // keep at least the strongest link
    connections[best] = best_w;
    best->connections[this] = best_w;
    best->sortConnections();
  }
  sortConnections();
  if (!parent && best && best->id < id) {
    parent = best;
    best->children.insert(this);
  }
}

void KeyFrame::eraseConnection(KeyFrame* kf) {
  if (connections.erase(kf)) sortConnections();
}

std::vector<KeyFrame*> KeyFrame::bestCovisibles(int n) const {
  std::vector<KeyFrame*> out;
  for (KeyFrame* kf : ordered_connections) {
    if ((int)out.size() >= n) break;
    if (!kf->bad) out.push_back(kf);
  }
  return out;
}

int KeyFrame::trackedMapPoints(int min_obs) const {
  int n = 0;
  for (const auto& mp : map_points) {
    if (mp && !mp->bad && mp->observationWeight() >= min_obs) ++n;
  }
  return n;
}

}  // namespace tkgslam::data
