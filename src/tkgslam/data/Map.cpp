#include "tkgslam/data/Map.h"

namespace tkgslam::data {

void Map::addKeyFrame(const std::shared_ptr<KeyFrame>& kf) {
  keyframes_[kf->id] = kf;
  all_keyframes_[kf->id] = kf;
}

void Map::addMapPoint(const std::shared_ptr<MapPoint>& mp) { points_[mp->id] = mp; }

void Map::eraseMapPoint(MapPoint* mp) {
  if (mp->bad) return;
  mp->bad = true;
  for (const auto& [kf, idx] : mp->observations) {
    if (kf->map_points[idx].get() == mp) kf->eraseMapPoint(idx);
  }
  mp->observations.clear();
  points_.erase(mp->id);
}

void Map::eraseObservation(MapPoint* mp, KeyFrame* kf) {
  auto it = mp->observations.find(kf);
  if (it == mp->observations.end()) return;
  if (kf->map_points[it->second].get() == mp) kf->eraseMapPoint(it->second);
  mp->observations.erase(it);
  if (mp->reference == kf && !mp->observations.empty()) mp->reference = mp->observations.begin()->first;
  if (mp->observationWeight() <= 2) eraseMapPoint(mp);
}

void Map::replaceMapPoint(MapPoint* mp, const std::shared_ptr<MapPoint>& by) {
  if (mp == by.get() || mp->bad) return;
  auto observations = mp->observations;
  mp->observations.clear();
  mp->bad = true;
  mp->replaced_by = by;
  for (const auto& [kf, idx] : observations) {
    if (!by->observations.count(kf)) {
      kf->map_points[idx] = by;
      by->observations[kf] = idx;
    } else {
      kf->eraseMapPoint(idx);
    }
  }
  by->found += mp->found;
  by->visible += mp->visible;
  by->computeDistinctiveDescriptor();
  points_.erase(mp->id);
}

void Map::eraseKeyFrame(KeyFrame* kf) {
  if (kf->bad || kf->not_erase) return;
  for (auto& [other, w] : kf->connections) other->eraseConnection(kf);
  for (size_t i = 0; i < kf->map_points.size(); ++i) {
    if (auto mp = kf->map_points[i]) eraseObservation(mp.get(), kf);
  }
  kf->connections.clear();
  kf->ordered_connections.clear();
  // Children are re-attached to this keyframe's parent.
  KeyFrame* parent = kf->parent;
  while (parent && parent->bad) parent = parent->parent;
  for (KeyFrame* child : kf->children) {
    child->parent = parent;
    if (parent) parent->children.insert(child);
  }
  kf->children.clear();
  if (parent) {
    parent->children.erase(kf);
    kf->T_c_parent = kf->T_cw() * parent->T_wc();
  }
  kf->parent = parent;
  kf->bad = true;
  kf->releaseFeatures();
  keyframes_.erase(kf->id);
}

std::shared_ptr<KeyFrame> Map::keyFrame(long id) const {
  auto it = all_keyframes_.find(id);
  return it == all_keyframes_.end() ? nullptr : it->second;
}

std::vector<std::shared_ptr<KeyFrame>> Map::keyFrames() const {
  std::vector<std::shared_ptr<KeyFrame>> out;
  out.reserve(keyframes_.size());
  for (const auto& kv : keyframes_) out.push_back(kv.second);
  return out;
}

std::vector<std::shared_ptr<MapPoint>> Map::mapPoints() const {
  std::vector<std::shared_ptr<MapPoint>> out;
  out.reserve(points_.size());
  for (const auto& kv : points_) out.push_back(kv.second);
  return out;
}

void Map::clearActive(size_t keep_features) {
  for (auto& kv : points_) kv.second->bad = true;
  points_.clear();
  size_t left = keyframes_.size();
  for (auto& kv : keyframes_) {
    kv.second->connections.clear();
    kv.second->ordered_connections.clear();
    if (left-- > keep_features) kv.second->releaseFeatures();
    kv.second->not_erase = true;
  }
  keyframes_.clear();
  segment_first_kf_id_ = next_kf_id_;
  ++generation_;
}

void Map::transformActive(const Pose& T_new_old) {
  const Pose T_old_new = T_new_old.inverse();
  for (auto it = all_keyframes_.lower_bound(segment_first_kf_id_); it != all_keyframes_.end(); ++it) {
    it->second->setPose(orthonormalized(it->second->T_cw() * T_old_new));
  }
  for (auto& kv : points_) {
    kv.second->pos_w = T_new_old * kv.second->pos_w;
    kv.second->normal = T_new_old.linear() * kv.second->normal;
  }
  ++generation_;
}

}  // namespace tkgslam::data
