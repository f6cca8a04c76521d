#include "tkgslam/mapping/LocalMapper.h"

#include <chrono>
#include <mutex>
#include <optional>

#include <spdlog/spdlog.h>

#include "tkgslam/optimize/MapBundle.h"

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
  std::optional<optimize::MapBundle> bundle;
  long generation = 0;
  {
    std::lock_guard<std::mutex> lock(map_.mutex());
    generation = map_.generation();
    // Local window: the keyframe and all its covisible keyframes.
    std::vector<KeyFrame*> local{&kf};
    for (KeyFrame* n : kf.ordered_connections) {
      if (!n->bad) local.push_back(n);
    }
    bundle.emplace(map_, local, pyr_);
  }
  if (bundle->problem().observations.empty()) return;
  optimize::BundleOptions opts;
  opts.iterations_second = cfg_.mapping.local_ba_iterations;
  opts.threads = cfg_.deterministic ? 1 : 2;
  // Optional hold (mapping.max_keyframe_shift_*): the new keyframe comes first in the problem.
  // Where the solution moves it far from where tracking put it (static scenes never do; on the
  // composites a keyframe whose view is mostly on people is weakly constrained), it is solved
  // again from the start with that keyframe fixed.
  const bool hold = cfg_.mapping.max_keyframe_shift_m > 0 || cfg_.mapping.max_keyframe_shift_deg > 0;
  std::optional<optimize::BundleProblem> start;
  if (hold && !bundle->problem().fixed_pose[0]) start = bundle->problem();
  auto outlier = optimize::solveBundle(bundle->problem(), K_, opts);
  if (start && shiftedTooFar(start->poses[0], bundle->problem().poses[0])) {
    bundle->problem() = std::move(*start);
    bundle->problem().fixed_pose[0] = 1;
    outlier = optimize::solveBundle(bundle->problem(), K_, opts);
    stats_.keyframes_held++;
  }
  {
    std::lock_guard<std::mutex> lock(map_.mutex());
    // Tracking moved the map into another frame (or started a new one) while the solver ran.
    if (map_.generation() != generation) return;
    bundle->apply(map_, outlier, pyr_);
  }
  stats_.last_ba_ms = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}

bool LocalMapper::shiftedTooFar(const Pose& tracked, const Pose& solved) const {
  const auto& m = cfg_.mapping;
  const auto [metres, deg] = poseGap(solved, tracked);
  const bool too_far = (m.max_keyframe_shift_m > 0 && metres > m.max_keyframe_shift_m) ||
                       (m.max_keyframe_shift_deg > 0 && deg > m.max_keyframe_shift_deg);
  if (too_far) spdlog::debug("local BA moved the new keyframe {:.3f} m / {:.2f} deg from its tracked pose: held there", metres, deg);
  return too_far;
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
