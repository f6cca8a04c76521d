#include "tkgslam/optimize/MapBundle.h"

#include <map>
#include <set>

namespace tkgslam::optimize {

using data::KeyFrame;
using data::MapPoint;

MapBundle::MapBundle(const data::Map& map, const std::vector<KeyFrame*>& window, const feature::ScalePyramid& pyr) {
  const std::set<const KeyFrame*> free(window.begin(), window.end());
  std::map<long, int> cam_index;  // keyframe id -> problem pose
  auto addCam = [&](KeyFrame* k) {
    const auto it = cam_index.find(k->id);
    if (it != cam_index.end()) return it->second;
    const int i = int(cams_.size());
    cam_index[k->id] = i;
    cams_.push_back(map.keyFrame(k->id));
    problem_.poses.push_back(k->T_cw());
    problem_.fixed_pose.push_back(!free.count(k) || k->id == 0 ? 1 : 0);
    return i;
  };
  for (KeyFrame* k : window) addCam(k);
  for (KeyFrame* k : window) {
    for (const auto& mp : k->map_points) {
      if (!mp || mp->bad || !taken_.insert(mp.get()).second) continue;
      const int pi = int(points_.size());
      points_.push_back(mp);
      problem_.points.push_back(mp->pos_w);
      for (const auto& [obs_kf, idx] : mp->observations) {
        if (obs_kf->bad) continue;
        const auto& F = *obs_kf->features;
        BundleObservation o;
        o.camera = addCam(obs_kf);
        o.point = pi;
        o.uv = Vec2(F.ideal[idx].pt.x, F.ideal[idx].pt.y);
        o.u_right = F.u_right[idx];
        o.information = pyr.inv_sigma2[F.ideal[idx].octave];
        problem_.observations.push_back(o);
        observed_.emplace_back(obs_kf, mp.get());
      }
    }
  }
}

void MapBundle::fix(const KeyFrame* kf) {
  for (size_t i = 0; i < cams_.size(); ++i) {
    if (cams_[i].get() == kf) problem_.fixed_pose[i] = 1;
  }
}

void MapBundle::apply(data::Map& map, const std::vector<char>& outlier, const feature::ScalePyramid& pyr) const {
  for (size_t k = 0; k < outlier.size() && k < observed_.size(); ++k) {
    if (!outlier[k]) continue;
    auto [kf, mp] = observed_[k];
    if (!mp->bad && !kf->bad) map.eraseObservation(mp, kf);
  }
  for (size_t i = 0; i < cams_.size(); ++i) {
    if (!problem_.fixed_pose[i] && !cams_[i]->bad) cams_[i]->setPose(problem_.poses[i]);
  }
  for (size_t i = 0; i < points_.size(); ++i) {
    if (points_[i]->bad) continue;
    points_[i]->pos_w = problem_.points[i];
    points_[i]->updateNormalAndDepth(pyr);
  }
}

}  // namespace tkgslam::optimize
