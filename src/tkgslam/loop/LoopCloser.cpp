#include "tkgslam/loop/LoopCloser.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <mutex>
#include <optional>
#include <set>
#include <tuple>

#include <spdlog/spdlog.h>

#include "tkgslam/common/Elapsed.h"
#include "tkgslam/data/Frame.h"
#include "tkgslam/optimize/FramePose.h"
#include "tkgslam/optimize/MapBundle.h"
#include "tkgslam/optimize/PoseGraphOptimizer.h"

namespace tkgslam::loop {

using data::KeyFrame;
using data::MapPoint;

namespace {

constexpr double kRadToDeg = 180.0 / M_PI;
/// Covisibility links this strong become pose-graph edges (ORB-SLAM2's essential graph: 100).
constexpr int kCovisibilityEdge = 100;
/// Keyframes on either side whose points are fused after a correction.
constexpr int kFuseNeighbours = 10;
/// A second detection confirms the first when the corrections differ by less than this at its camera.
constexpr double kAgreeM = 0.03;
constexpr double kAgreeDeg = 2.0;
/// Weight of the loop edge: far above a covisibility edge's (shared points, a few hundred).
constexpr double kLoopEdgeWeight = 1e5;
/// Points per old keyframe (most observed first) used to rank the candidates by appearance.
constexpr size_t kScoringPoints = 300;
/// Descriptor matches a candidate needs to be verified, and RANSAC inliers before the guided search.
constexpr int kMinDescriptorMatches = 15;
constexpr int kMinPnpInliers = 12;

}  // namespace

LoopCloser::LoopCloser(data::Map& map, const camera::PinholeCamera& camera, const feature::ScalePyramid& pyramid,
                       const SlamConfig& config)
    : map_(map), cam_(camera), pyr_(pyramid), cfg_(config), matcher_(camera, pyramid, config.depth.baseline_fx),
      K_(optimize::intrinsicsOf(camera.fx(), camera.fy(), camera.cx(), camera.cy(), config.depth.baseline_fx)) {}

bool LoopCloser::process(const std::shared_ptr<KeyFrame>& kf) {
  if (!cfg_.loop.enabled) return false;
  const auto t0 = std::chrono::steady_clock::now();
  ++stats_.keyframes_checked;
  std::optional<Loop> loop = detect(kf);
  stats_.total_ms += msSince(t0);
  if (!loop) {
    // A detection may wait a few keyframes for its confirmation: the keyframes in between may see
    // too little of the old place (a person in front, a blurred image).
    if (pending_ && ++pending_waited_ >= cfg_.loop.confirm_within) pending_.reset();
    return false;
  }
  // With loop.confirm one detection may be a coincidence (a repeated texture, a mover's points
  // that slipped through): one of the next loop.confirm_within keyframes must find the same correction.
  const bool confirmed = !cfg_.loop.confirm || (pending_ && agree(*pending_, *loop));
  if (!confirmed) {
    pending_waited_ = 0;
    pending_ = std::move(loop);
    return false;
  }
  pending_.reset();
  const auto t1 = std::chrono::steady_clock::now();
  const bool closed = close(*loop);
  if (closed && cfg_.loop.global_ba_iterations > 0) globalBundleAdjustment();
  stats_.total_ms += msSince(t1);
  return closed;
}

std::vector<std::shared_ptr<KeyFrame>> LoopCloser::candidatesFor(const KeyFrame& kf) const {
  std::vector<std::shared_ptr<KeyFrame>> out;
  for (const auto& c : map_.keyFrames()) {
    if (c->bad || !c->features || c->id > kf.id - cfg_.loop.min_keyframe_gap) continue;
    if (kf.connections.count(c.get())) continue;  // covisible: local BA keeps the two consistent
    out.push_back(c);
  }
  return out;
}

std::vector<std::shared_ptr<MapPoint>> LoopCloser::pointsAround(const KeyFrame& kf) {
  std::vector<const KeyFrame*> sources{&kf};
  for (KeyFrame* n : kf.bestCovisibles(kFuseNeighbours)) sources.push_back(n);
  std::vector<std::shared_ptr<MapPoint>> out;
  std::set<long> taken;
  for (const KeyFrame* src : sources) {
    for (const auto& mp : src->map_points) {
      if (mp && !mp->bad && taken.insert(mp->id).second) out.push_back(mp);
    }
  }
  return out;
}

std::shared_ptr<MapPoint> LoopCloser::copyOf(const MapPoint& mp) {
  auto copy = std::make_shared<MapPoint>(mp.id, mp.pos_w, nullptr, mp.descriptor);
  copy->normal = mp.normal;
  copy->min_distance = mp.min_distance;
  copy->max_distance = mp.max_distance;
  return copy;
}

std::vector<std::shared_ptr<KeyFrame>> LoopCloser::mostSimilar(const data::FrameFeatures& query,
                                                               std::vector<std::shared_ptr<KeyFrame>> candidates) {
  const size_t n = size_t(cfg_.loop.word_candidates);
  if (n == 0 || candidates.size() <= n) return candidates;
  std::vector<place::DatabaseEntry> entries;
  {
    std::lock_guard<std::mutex> lock(map_.mutex());
    entries = place::entriesOf(map_.keyFrames());
  }
  // Training (a fraction of a second, once the map has doubled) runs without the lock.
  if (places_.update(entries)) {
    ++stats_.vocabulary_trainings;
    spdlog::debug("loop detection: vocabulary of {} words trained on {} keyframes", places_.words(), entries.size());
  }
  if (!places_.trained()) return candidates;  // no descriptors to learn words from
  std::vector<long> ids;
  for (const auto& c : candidates) ids.push_back(c->id);
  std::sort(ids.begin(), ids.end());
  std::vector<long> similar = places_.mostSimilar(query, n, &ids);
  std::sort(similar.begin(), similar.end());
  // In map order, as without the index.
  candidates.erase(std::remove_if(candidates.begin(), candidates.end(),
                                  [&](const auto& c) { return !std::binary_search(similar.begin(), similar.end(), c->id); }),
                   candidates.end());
  return candidates;
}

std::optional<LoopCloser::Loop> LoopCloser::detect(const std::shared_ptr<KeyFrame>& kf) {
  std::shared_ptr<const data::FrameFeatures> features;
  std::vector<std::shared_ptr<KeyFrame>> candidates;
  {
    std::lock_guard<std::mutex> lock(map_.mutex());
    if (kf->bad || !kf->features) return std::nullopt;
    features = kf->features;
    candidates = candidatesFor(*kf);
  }
  candidates = mostSimilar(*features, std::move(candidates));
  stats_.candidates_considered += int(candidates.size());
  std::vector<std::unique_ptr<KeyFrame>> probes;
  Loop base;
  {
    std::lock_guard<std::mutex> lock(map_.mutex());
    if (kf->bad) return std::nullopt;
    base.kf = kf;
    base.T_cw_map = kf->T_cw();
    base.generation = map_.generation();
    for (const auto& c : candidates) {
      if (!c->bad) probes.push_back(scoringProbe(*c));
    }
  }
  if (probes.empty()) return std::nullopt;
  // The matcher and the pose solvers read a Frame's features and never write them.
  const data::Frame frame(kf->frame_id, 0.0, std::const_pointer_cast<data::FrameFeatures>(features));
  std::optional<Loop> best = bestVerified(frame, probes, base);
  if (!best) return std::nullopt;
  ++stats_.detected;
  return best;
}

std::unique_ptr<KeyFrame> LoopCloser::scoringProbe(const KeyFrame& c) {
  // Most observed first; among equals spread over the keypoint list (it is ordered by level
  // and image cell) by a fixed scrambling of the index.
  std::vector<std::tuple<int, size_t, size_t>> by_obs;
  for (size_t i = 0; i < c.map_points.size(); ++i) {
    const auto& mp = c.map_points[i];
    if (mp && !mp->bad) by_obs.emplace_back(-int(mp->observations.size()), (i * 7919) % 4093, i);
  }
  std::sort(by_obs.begin(), by_obs.end());
  if (by_obs.size() > kScoringPoints) by_obs.resize(kScoringPoints);
  auto probe = std::make_unique<KeyFrame>(c.id, c.frame_id, c.timestamp, c.features, c.T_cw());
  probe->map_points.resize(c.map_points.size());
  for (const auto& [obs, scrambled, i] : by_obs) probe->map_points[i] = copyOf(*c.map_points[i]);
  return probe;
}

std::optional<LoopCloser::Loop> LoopCloser::bestVerified(const data::Frame& frame,
                                                         const std::vector<std::unique_ptr<KeyFrame>>& probes,
                                                         const Loop& base) {
  const KeyFrame& kf = *base.kf;
  // Appearance first: the old keyframes whose points match most of the new keyframe's keypoints.
  std::vector<std::pair<int, size_t>> scored;
  std::vector<std::vector<std::shared_ptr<MapPoint>>> matches(probes.size());
  for (size_t k = 0; k < probes.size(); ++k) {
    const int n = matcher_.searchByDescriptors(*probes[k], frame, matches[k]);
    if (n >= kMinDescriptorMatches) scored.emplace_back(-n, k);
  }
  std::stable_sort(scored.begin(), scored.end());
  if (scored.size() > size_t(cfg_.loop.candidates)) scored.resize(size_t(cfg_.loop.candidates));

  std::optional<Loop> best;
  for (const auto& [minus_n, k] : scored) {
    const KeyFrame& probe = *probes[k];
    // All the points the old keyframe's neighbourhood has, for the search guided by the pose.
    std::vector<std::shared_ptr<MapPoint>> nearby;
    {
      std::lock_guard<std::mutex> lock(map_.mutex());
      const auto old = map_.keyFrame(probe.id);
      if (!old || old->bad) continue;
      for (const auto& mp : pointsAround(*old)) nearby.push_back(copyOf(*mp));
    }
    std::optional<Loop> loop = verify(frame, matches[k], nearby, base);
    spdlog::debug("keyframe {} (frame {}) against keyframe {}: {} descriptor matches, {} inliers", kf.id,
                  kf.frame_id, probe.id, -minus_n, loop ? loop->inliers : 0);
    if (!loop) continue;
    ++stats_.candidates_matched;
    const double shift_m = loop->shiftM(), angle_deg = loop->angleDeg();
    spdlog::debug("keyframe {}: loop with keyframe {}: {} inliers, the map has it {:.3f} m / {:.2f} deg off", kf.id,
                  probe.id, loop->inliers, shift_m, angle_deg);
    if (shift_m < cfg_.loop.min_correction_m && angle_deg < cfg_.loop.min_correction_deg) {
      ++stats_.consistent;
      continue;
    }
    if (!best || loop->inliers > best->inliers) {
      best = std::move(loop);
      best->old_id = probe.id;
    }
  }
  return best;
}

std::optional<LoopCloser::Loop> LoopCloser::verify(const data::Frame& frame,
                                                   const std::vector<std::shared_ptr<MapPoint>>& descriptor_matches,
                                                   const std::vector<std::shared_ptr<MapPoint>>& nearby,
                                                   const Loop& base) const {
  data::Frame probe = frame;
  probe.map_points = descriptor_matches;
  Pose T_cw = Pose::Identity();
  if (optimize::solvePnpRansac(probe, cam_, probe.map_points, T_cw) < kMinPnpInliers) return std::nullopt;
  probe.T_cw = T_cw;
  std::fill(probe.outlier.begin(), probe.outlier.end(), 0);
  if (optimize::optimizeFramePose(probe, K_, pyr_) < kMinPnpInliers) return std::nullopt;
  // With a pose, the old side's points are searched where they project: many more matches than
  // appearance alone finds across the change of viewpoint (ORB-SLAM2 does the same after Sim3).
  for (int i = 0; i < probe.size(); ++i) {
    if (probe.outlier[i]) probe.map_points[i].reset();
  }
  std::fill(probe.outlier.begin(), probe.outlier.end(), 0);
  std::vector<std::shared_ptr<MapPoint>> visible;
  for (const auto& mp : nearby) {
    if (matcher_.isInFrustum(*mp, probe.T_cw, 0.5)) visible.push_back(mp);
  }
  matcher_.searchByProjection(probe, visible, 3.0f);
  const int inliers = optimize::optimizeFramePose(probe, K_, pyr_);
  if (inliers < cfg_.loop.min_inliers) return std::nullopt;
  Loop loop = base;
  loop.T_cw_loop = orthonormalized(probe.T_cw);
  loop.inliers = inliers;
  return loop;
}

bool LoopCloser::agree(const Loop& a, const Loop& b) {
  const Pose D = a.correction().inverse() * b.correction();
  const Vec3 c = b.T_cw_map.inverse().translation();
  return (D * c - c).norm() < kAgreeM && rotationAngle(D.linear()) * kRadToDeg < kAgreeDeg;
}

bool LoopCloser::close(const Loop& loop) {
  std::lock_guard<std::mutex> lock(map_.mutex());
  // A new segment or a re-anchoring moved the map while the loop was being verified.
  const auto old = map_.keyFrame(loop.old_id);
  if (map_.generation() != loop.generation || loop.kf->bad || !old || old->bad) return false;
  const auto nodes = map_.keyFrames();
  std::optional<optimize::PoseGraph> graph = poseGraphFor(nodes, loop, *old);
  if (!graph) return false;
  optimize::PoseGraphOptions opts;
  opts.iterations = 50;
  if (!optimize::optimizePoseGraph(*graph, opts)) return false;
  applyCorrection(nodes, graph->poses);
  const int fused = fuseOldSide(*loop.kf, *old);
  map_.noteCorrection();
  stats_.closed++;
  stats_.last_correction_m = loop.shiftM();
  stats_.last_correction_deg = loop.angleDeg();
  spdlog::info("loop closed: keyframe {} (frame {}) with keyframe {} (frame {}), {} inliers; the map had it {:.3f} m / "
               "{:.1f} deg off; {} keyframes corrected, {} points fused",
               loop.kf->id, loop.kf->frame_id, old->id, old->frame_id, loop.inliers, stats_.last_correction_m,
               stats_.last_correction_deg, nodes.size(), fused);
  return true;
}

std::optional<optimize::PoseGraph> LoopCloser::poseGraphFor(const std::vector<std::shared_ptr<KeyFrame>>& nodes,
                                                            const Loop& loop, const KeyFrame& old) {
  std::map<const KeyFrame*, int> index;
  optimize::PoseGraph graph;
  for (const auto& k : nodes) {
    index[k.get()] = int(graph.poses.size());
    graph.poses.push_back(k->T_cw());
    graph.fixed.push_back(graph.poses.size() == 1 ? 1 : 0);  // the segment's oldest keyframe holds the gauge
  }
  auto addEdge = [&](const KeyFrame* a, const KeyFrame* b, double weight) {
    const auto ia = index.find(a), ib = index.find(b);
    if (ia == index.end() || ib == index.end()) return;
    graph.edges.push_back({ia->second, ib->second, a->T_cw() * b->T_wc(), weight});
  };
  // Edges weighted by shared points: the frames where the map forked share few with those
  // before, so the correction goes there rather than into the well-tied keyframes either side.
  for (const auto& k : nodes) {
    if (k->parent && !k->parent->bad) {
      const auto w = k->connections.find(k->parent);
      addEdge(k.get(), k->parent, w == k->connections.end() ? 1.0 : double(w->second));
    }
    for (const auto& [other, w] : k->connections) {
      if (w >= kCovisibilityEdge && other->id < k->id && other != k->parent && !other->bad) addEdge(k.get(), other, w);
    }
  }
  const auto ik = index.find(loop.kf.get()), io = index.find(&old);
  if (ik == index.end() || io == index.end()) return std::nullopt;
  // The loop edge outweighs any chain of covisibility edges: the measurement is trusted.
  graph.edges.push_back({ik->second, io->second, loop.T_cw_loop * old.T_wc(), kLoopEdgeWeight});
  return graph;
}

void LoopCloser::applyCorrection(const std::vector<std::shared_ptr<KeyFrame>>& nodes, const std::vector<Pose>& corrected) {
  // Points move with their reference keyframe (or the first observer still in the map).
  std::map<const KeyFrame*, Pose> moved;  // T_new_old of each keyframe's attached points
  for (size_t k = 0; k < nodes.size(); ++k) moved[nodes[k].get()] = corrected[k].inverse() * nodes[k]->T_cw();
  for (const auto& mp : map_.mapPoints()) {
    const KeyFrame* ref = mp->reference && moved.count(mp->reference) ? mp->reference : nullptr;
    for (auto it = mp->observations.begin(); !ref && it != mp->observations.end(); ++it) {
      if (moved.count(it->first)) ref = it->first;
    }
    if (!ref) continue;
    const Pose& T = moved.at(ref);
    mp->pos_w = T * mp->pos_w;
    mp->normal = T.linear() * mp->normal;
  }
  for (size_t k = 0; k < nodes.size(); ++k) nodes[k]->setPose(orthonormalized(corrected[k]));
}

int LoopCloser::fuseOldSide(KeyFrame& kf, const KeyFrame& old) {
  std::vector<KeyFrame*> targets{&kf};
  for (KeyFrame* n : kf.bestCovisibles(kFuseNeighbours)) targets.push_back(n);
  const std::vector<std::shared_ptr<MapPoint>> old_points = pointsAround(old);
  int fused = 0;
  for (KeyFrame* t : targets) {
    if (!t->bad && t->features) fused += matcher_.fuse(map_, *t, old_points);
  }
  for (KeyFrame* t : targets) {
    if (!t->bad && t->features) t->updateConnections();
  }
  return fused;
}

bool LoopCloser::globalBundleAdjustment() {
  const auto t0 = std::chrono::steady_clock::now();
  std::optional<optimize::MapBundle> bundle;
  std::vector<Pose> before;  // T_cw of each problem keyframe as copied
  long generation = 0;
  {
    std::lock_guard<std::mutex> lock(map_.mutex());
    generation = map_.generation();
    std::vector<KeyFrame*> window;
    for (const auto& k : map_.keyFrames()) {
      if (!k->bad && k->features) window.push_back(k.get());
    }
    if (window.size() < 2) return false;
    bundle.emplace(map_, window, pyr_);
    bundle->fix(window.front());  // the segment's oldest keyframe holds the gauge, as in close()
    before = bundle->problem().poses;
  }
  optimize::BundleOptions opts;
  opts.iterations_second = cfg_.loop.global_ba_iterations;
  opts.threads = cfg_.deterministic ? 1 : 2;
  const auto outlier = optimize::solveBundle(bundle->problem(), K_, opts);

  std::lock_guard<std::mutex> lock(map_.mutex());
  // A new segment or a re-anchoring moved the map while the solver ran.
  if (map_.generation() != generation) return false;
  // What the solution does to each keyframe's surroundings: T_new_old (old world -> new world).
  std::map<const KeyFrame*, Pose> moved;
  const auto& cams = bundle->keyFrames();
  for (size_t i = 0; i < cams.size(); ++i) moved[cams[i].get()] = bundle->problem().poses[i].inverse() * before[i];
  bundle->apply(map_, outlier, pyr_);
  // Keyframes tracking made while the solver ran follow their nearest ancestor in the problem
  // (ids grow along the spanning tree, so ancestors come first) ...
  for (const auto& k : map_.keyFrames()) {
    if (moved.count(k.get())) continue;
    const auto parent = k->parent ? moved.find(k->parent) : moved.end();
    const Pose T = parent == moved.end() ? Pose::Identity() : parent->second;
    moved[k.get()] = T;
    k->setPose(orthonormalized(k->T_cw() * T.inverse()));
  }
  // ... and so do the points they made.
  for (const auto& mp : map_.mapPoints()) {
    if (bundle->contains(*mp) || !mp->reference) continue;
    const auto it = moved.find(mp->reference);
    if (it == moved.end()) continue;
    mp->pos_w = it->second * mp->pos_w;
    mp->normal = it->second.linear() * mp->normal;
  }
  map_.noteCorrection();
  stats_.global_bundles++;
  stats_.last_global_ba_ms = msSince(t0);
  spdlog::info("global bundle adjustment: {} keyframes, {} points, {} observations ({} outliers) in {:.0f} ms", cams.size(),
               bundle->problem().points.size(), outlier.size(), std::count(outlier.begin(), outlier.end(), 1),
               stats_.last_global_ba_ms);
  return true;
}

}  // namespace tkgslam::loop
