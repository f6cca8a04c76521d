#include "tkgslam/mapping/LocalMapper.h"

#include <chrono>
#include <mutex>

namespace tkgslam::mapping {

using data::KeyFrame;
using data::MapPoint;

LocalMapper::LocalMapper(data::Map& map, const camera::PinholeCamera& camera, const feature::ScalePyramid& pyramid,
                         const SlamConfig& config)
    : map_(map), cam_(camera), pyr_(pyramid), cfg_(config), matcher_(camera, pyramid, config.depth.baseline_fx),
      K_(optimize::intrinsicsOf(camera.fx(), camera.fy(), camera.cx(), camera.cy(), config.depth.baseline_fx)) {}

void LocalMapper::process(const std::shared_ptr<KeyFrame>& kf, bool more_pending) {
  {
    std::lock_guard<std::mutex> lock(map_.mutex());
    if (kf->bad) return;
    for (const auto& mp : kf->map_points) {
      if (!mp || mp->bad) continue;
      if (mp->first_keyframe_id == kf->id) {
        recent_points_.push_back(mp);
      } else {
        mp->updateNormalAndDepth(pyr_);
        mp->computeDistinctiveDescriptor();
      }
    }
    kf->updateConnections();
    cullRecentPoints(*kf);
    fuseWithNeighbours(*kf);
  }
  if (!more_pending && cfg_.mapping.local_ba_iterations > 0) localBundleAdjustment(*kf);
  if (cfg_.mapping.cull_keyframes) {
    std::lock_guard<std::mutex> lock(map_.mutex());
    cullKeyFrames(*kf);
  }
  stats_.keyframes_processed++;
}

void LocalMapper::cullRecentPoints(KeyFrame& kf) {
  constexpr int kMinObservations = 3;
  for (auto it = recent_points_.begin(); it != recent_points_.end();) {
    MapPoint* mp = it->get();
    const long age = kf.id - mp->first_keyframe_id;
    if (mp->bad) {
      it = recent_points_.erase(it);
    } else if (mp->foundRatio() < 0.25f || (age >= 2 && mp->observationWeight() <= kMinObservations)) {
      map_.eraseMapPoint(mp);
      stats_.points_culled++;
      it = recent_points_.erase(it);
    } else if (age >= 3) {
      it = recent_points_.erase(it);
    } else {
      ++it;
    }
  }
}

void LocalMapper::fuseWithNeighbours(KeyFrame& kf) {
  std::vector<KeyFrame*> targets;
  for (KeyFrame* n : kf.bestCovisibles(cfg_.mapping.covisible_keyframes)) {
    if (n->bad || n->fuse_target_for == kf.id) continue;
    n->fuse_target_for = kf.id;
    targets.push_back(n);
  }
  const size_t first_ring = targets.size();
  for (size_t k = 0; k < first_ring; ++k) {
    for (KeyFrame* n2 : targets[k]->bestCovisibles(5)) {
      if (n2->bad || n2->fuse_target_for == kf.id || n2 == &kf) continue;
      n2->fuse_target_for = kf.id;
      targets.push_back(n2);
    }
  }
  // Current keyframe's points into the neighbours ...
  for (KeyFrame* t : targets) {
    auto pts = kf.map_points;  // copy: fusion may replace entries
    stats_.points_fused += matcher_.fuse(map_, *t, pts);
  }
  // ... and the neighbours' points into the current keyframe.
  std::vector<std::shared_ptr<MapPoint>> candidates;
  for (KeyFrame* t : targets) {
    for (const auto& mp : t->map_points) {
      if (!mp || mp->bad || mp->fuse_for == kf.id) continue;
      mp->fuse_for = kf.id;
      candidates.push_back(mp);
    }
  }
  stats_.points_fused += matcher_.fuse(map_, kf, candidates);
  for (const auto& mp : kf.map_points) {
    if (!mp || mp->bad) continue;
    mp->computeDistinctiveDescriptor();
    mp->updateNormalAndDepth(pyr_);
  }
  kf.updateConnections();
}

void LocalMapper::localBundleAdjustment(KeyFrame& kf) {
  const auto t0 = std::chrono::steady_clock::now();
  optimize::BundleProblem problem;
  std::vector<std::shared_ptr<KeyFrame>> cams;
  std::vector<std::shared_ptr<MapPoint>> points;
  std::vector<std::pair<KeyFrame*, MapPoint*>> obs_refs;
  long generation = 0;
  {
    std::lock_guard<std::mutex> lock(map_.mutex());
    generation = map_.generation();
    // Local window: the keyframe and all its covisible keyframes.
    std::vector<KeyFrame*> local{&kf};
    kf.ba_local_for = kf.id;
    for (KeyFrame* n : kf.ordered_connections) {
      if (n->bad) continue;
      n->ba_local_for = kf.id;
      local.push_back(n);
    }
    std::map<long, int> cam_index;  // keyframe id -> camera index
    auto addCam = [&](KeyFrame* k, bool fixed) {
      auto it = cam_index.find(k->id);
      if (it != cam_index.end()) return it->second;
      const int i = int(cams.size());
      cam_index[k->id] = i;
      cams.push_back(map_.keyFrame(k->id));
      problem.poses.push_back(k->T_cw());
      problem.fixed_pose.push_back(fixed || k->id == 0 ? 1 : 0);
      return i;
    };
    for (KeyFrame* k : local) addCam(k, false);
    for (KeyFrame* k : local) {
      for (const auto& mp : k->map_points) {
        if (!mp || mp->bad || mp->ba_local_for == kf.id) continue;
        mp->ba_local_for = kf.id;
        const int pi = int(points.size());
        points.push_back(mp);
        problem.points.push_back(mp->pos_w);
        for (const auto& [obs_kf, idx] : mp->observations) {
          if (obs_kf->bad) continue;
          // Keyframes outside the window that see local points are fixed.
          const int ci = addCam(obs_kf, obs_kf->ba_local_for != kf.id);
          const auto& F = *obs_kf->features;
          optimize::BundleObservation o;
          o.camera = ci;
          o.point = pi;
          o.uv = Vec2(F.ideal[idx].pt.x, F.ideal[idx].pt.y);
          o.u_right = F.u_right[idx];
          o.information = pyr_.inv_sigma2[F.ideal[idx].octave];
          problem.observations.push_back(o);
          obs_refs.emplace_back(obs_kf, mp.get());
        }
      }
    }
  }
  if (problem.observations.empty()) return;
  optimize::BundleOptions opts;
  opts.iterations_second = cfg_.mapping.local_ba_iterations;
  opts.threads = cfg_.deterministic ? 1 : 2;
  const auto outlier = optimize::solveBundle(problem, K_, opts);
  {
    std::lock_guard<std::mutex> lock(map_.mutex());
    // Tracking moved the map into another frame (or started a new one) while the solver ran.
    if (map_.generation() != generation) return;
    for (size_t k = 0; k < outlier.size(); ++k) {
      if (!outlier[k]) continue;
      auto [okf, mp] = obs_refs[k];
      if (!mp->bad && !okf->bad) map_.eraseObservation(mp, okf);
    }
    for (size_t i = 0; i < cams.size(); ++i) {
      if (!problem.fixed_pose[i] && !cams[i]->bad) cams[i]->setPose(problem.poses[i]);
    }
    for (size_t i = 0; i < points.size(); ++i) {
      if (points[i]->bad) continue;
      points[i]->pos_w = problem.points[i];
      points[i]->updateNormalAndDepth(pyr_);
    }
  }
  stats_.last_ba_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

void LocalMapper::cullKeyFrames(KeyFrame& kf) {
  constexpr int kObsThreshold = 3;
  for (KeyFrame* n : kf.bestCovisibles(int(kf.ordered_connections.size()))) {
    if (n->id == 0 || n->bad || n->not_erase) continue;
    const auto& F = *n->features;
    int points = 0, redundant = 0;
    for (size_t i = 0; i < n->map_points.size(); ++i) {
      const auto& mp = n->map_points[i];
      if (!mp || mp->bad) continue;
      if (F.depth[i] > cfg_.depth.close_threshold || F.depth[i] <= 0) continue;
      ++points;
      if (mp->observationWeight() <= kObsThreshold) continue;
      const int level = F.ideal[i].octave;
      int seen = 0;
      for (const auto& [other, idx] : mp->observations) {
        if (other == n) continue;
        if (other->features->ideal[idx].octave <= level + 1 && ++seen >= kObsThreshold) break;
      }
      if (seen >= kObsThreshold) ++redundant;
    }
    if (points > 0 && redundant > cfg_.mapping.keyframe_redundancy * points) {
      map_.eraseKeyFrame(n);
      stats_.keyframes_culled++;
    }
  }
}

}  // namespace tkgslam::mapping
