#include "tkgslam/tracking/Tracker.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <mutex>

#include <spdlog/spdlog.h>

#include "tkgslam/common/Elapsed.h"
#include "tkgslam/optimize/FramePose.h"
#include "tkgslam/tracking/TrajectoryRepair.h"

namespace tkgslam::tracking {

using data::Frame;
using data::KeyFrame;
using data::MapPoint;

Tracker::Tracker(data::Map& map, const camera::PinholeCamera& camera, const feature::ScalePyramid& pyramid,
                 const SlamConfig& config)
    : map_(map), cam_(camera), pyr_(pyramid), cfg_(config), matcher_(camera, pyramid, config.depth.baseline_fx),
      K_(optimize::intrinsicsOf(camera.fx(), camera.fy(), camera.cx(), camera.cy(), config.depth.baseline_fx)) {}

TrackResult Tracker::track(Frame frame, bool mapper_idle, int mapper_queue, const RefineKeypoints& refine) {
  std::lock_guard<std::mutex> lock(map_.mutex());
  const double timestamp = frame.timestamp;
  TrackResult result = trackLocked(std::move(frame), mapper_idle, mapper_queue, refine);
  // A tracked frame's record is the newest (lost frames interpolated now are inserted before it).
  if (result.tracked && !records_.empty() && records_.back().timestamp == timestamp) {
    result.T_wc = records_.back().T_cw().inverse();
  }
  return result;
}

TrackResult Tracker::trackLocked(Frame frame, bool mapper_idle, int mapper_queue, const RefineKeypoints& refine) {
  TrackResult result;
  result.blurred = checkBlurred(frame);
  result.covered = frame.box_cover >= cfg_.tracking.covered_ratio;
  if (state_ == TrackingState::NotInitialized) {
    // A map started on a blurred image would have a blurred first keyframe: wait for a sharp one.
    if (!result.blurred && initialize(frame, false)) {
      result.tracked = true;
      result.new_keyframe = last_kf_;
    }
    return result;
  }

  // A velocity needs two consecutive tracked frames (not one across a relocalisation gap).
  const bool after_loss = state_ == TrackingState::Lost;
  bool rescued = false;
  bool ok = estimatePose(frame, refine, &rescued);
  if (ok && jumpedFromMotionModel(frame)) {
    ok = false;
    result.jump_rejected = true;
  }
  if (ok) {
    keepTrackedFrame(std::move(frame), after_loss, rescued, mapper_idle, mapper_queue, result);
  } else if (!bridgeFrame(frame, result)) {
    loseFrame(frame, result);
  }
  return result;
}

bool Tracker::estimatePose(Frame& frame, const RefineKeypoints& refine, bool* rescued) {
  bool ok = false;
  if (state_ == TrackingState::Ok) {
    // Replace points fused by local mapping since the last frame.
    for (auto& mp : last_frame_->map_points) {
      if (mp && mp->replaced_by) mp = mp->replaced_by;
    }
    if (has_velocity_ && frame.id > last_reloc_frame_ + 1) {
      ok = trackWithMotionModel(frame);
      if (!ok) ok = trackReferenceKeyFrame(frame);
    } else {
      ok = trackReferenceKeyFrame(frame);
    }
  } else {
    ok = relocalize(frame);
  }
  if (ok) ok = trackLocalMap(frame);
  if (refine && state_ == TrackingState::Ok && (ok || has_velocity_)) {
    // The geometry check needs a pose: the tracked one, or - when the keypoints outside the boxes
    // were too few to track - the motion model's prediction. Keypoints it finds dynamic lose their
    // matches. Those it finds static are matched when the frame was not tracked yet (the motion
    // model's search includes them); on a frame already tracked, the second local-map pass finds
    // every local point marked by the first and only refines the pose without the dynamic ones, so
    // the re-admitted keypoints serve the keyframe's new points, not this pose. Searching the local
    // map again for them made the extreme composites far worse (TKGt extreme 0.0373 -> 0.1734 m;
    // bench/results/rematch_readmitted_300.md).
    if (!ok) frame.T_cw = predictPose();
    if (refine(frame, local_keyframes_) > 0) {
      // Keypoints it found dynamic lose their matches.
      for (int i = 0; i < frame.size(); ++i) {
        if (frame.features->excluded[i]) frame.map_points[i].reset();
      }
      const bool tracked_outside = ok;
      if (!ok) ok = trackWithMotionModel(frame) || trackReferenceKeyFrame(frame);
      if (ok) ok = trackLocalMap(frame);
      if (ok && !tracked_outside && cfg_.tracking.min_rescued_inliers > 0) {
        // Only the re-admitted keypoints track this frame, and the check re-admitted them using the
        // predicted pose: no independent support. Such poses drifted 2-9 cm per frame on the
        // extreme composites, and keyframes made from them passed the error on to the next.
        *rescued = true;
        ok = matches_inliers_ >= cfg_.tracking.min_rescued_inliers;
        spdlog::debug("frame {}: tracked only by re-admitted keypoints, {} inliers (need {})", frame.id,
                      matches_inliers_, cfg_.tracking.min_rescued_inliers);
      }
    }
  }
  return ok;
}

// Also right after bridged frames, with a tolerance growing with their number (so does the
// prediction's error): a tracked pose 35 cm off after one blurred frame was taken, and its
// keyframe misled the frames after it (high_shake composite, object mask: 0.0202 -> 0.0124 m).
// Not across a gap in the input (frames missing from the log): the camera may be anywhere.
bool Tracker::jumpedFromMotionModel(const Frame& frame) const {
  const int since_last = gap_frames_ + 1;  // frame periods since the last tracked frame
  return has_velocity_ && frame.id > last_reloc_frame_ + 1 &&
         frame.timestamp - last_frame_->timestamp < (since_last + 1.0) / cfg_.camera.fps &&
         poseJumped(frame.T_cw, since_last);
}

void Tracker::keepTrackedFrame(Frame&& frame, bool after_loss, bool rescued, bool mapper_idle, int mapper_queue,
                               TrackResult& result) {
  state_ = TrackingState::Ok;
  const int lost_frames = lost_frames_;
  lost_frames_ = 0;
  // Temporary visual-odometry points are not map points; forget them.
  for (int i = 0; i < frame.size(); ++i) {
    if (frame.map_points[i] && frame.map_points[i]->observations.empty()) {
      frame.map_points[i].reset();
      frame.outlier[i] = 0;
    }
  }
  temporal_points_.clear();
  if (result.blurred && !after_loss && gap_frames_ < maxGapFrames()) {
    // Tracked, but a blurred image is a poor keyframe and a poor frame to match the next one
    // against: the frame is not kept, and its pose only until the next sharp frame is tracked
    // (high_shake composite: T 0.0150 -> 0.0126 m, TKG 0.0172 -> 0.0137 m with them interpolated).
    ++gap_frames_;
    records_.push_back({frame.timestamp, reference_kf_, frame.T_cw * reference_kf_->T_wc(), true});
    result.tracked = true;
    result.inliers = matches_inliers_;
    return;
  }
  // After bridged frames the step spans several frames: the velocity is its per-frame share.
  // (No last frame: the first frame of a run in a loaded map.)
  if (last_frame_) velocity_ = orthonormalized(poseRoot(frame.T_cw * last_frame_->T_cw.inverse(), gap_frames_ + 1));
  has_velocity_ = !after_loss;
  if (spdlog::should_log(spdlog::level::debug)) {  // (not worth an acos per frame otherwise)
    spdlog::debug("frame {}: velocity {:.3f} m / {:.2f} deg per frame (over {} frames)", frame.id,
                  velocity_.translation().norm(), rotationAngle(velocity_.linear()) * 180.0 / M_PI, gap_frames_ + 1);
  }
  const int gap = gap_frames_;
  gap_frames_ = 0;
  predicted_frames_ = 0;
  // (A blurred frame gets here after a long run of them: it becomes the frame to match against,
  // but still no keyframe.)
  // (Nor a frame tracked only by re-admitted keypoints: see above.)
  if (!localization_only_ && !result.blurred && !rescued && needNewKeyFrame(frame, mapper_idle, mapper_queue)) {
    result.new_keyframe = createKeyFrame(frame);
  }
  if (result.new_keyframe && !anchor_candidates_.empty()) {
    result.reanchored = reanchorSegment(frame, result.interpolated_lost);
  }
  for (int i = 0; i < frame.size(); ++i) {
    if (frame.outlier[i]) frame.map_points[i].reset();
  }
  if (!frame.reference) frame.reference = reference_kf_;
  records_.push_back({frame.timestamp, frame.reference, frame.T_cw * frame.reference->T_wc()});
  if (cfg_.tracking.pose_check_m > 0) {
    // (Outliers and temporary points were dropped above: what is left are the inlier map points.)
    const auto& F = *frame.features;
    auto& kept = records_.back().matches;
    for (int i = 0; i < frame.size(); ++i) {
      if (!frame.map_points[i]) continue;
      kept.push_back({frame.map_points[i], F.ideal[i].pt.x, F.ideal[i].pt.y, F.u_right[i], F.ideal[i].octave});
    }
    if (records_.size() > kPoseCheckWindow) checkRecordPose(records_[records_.size() - 1 - kPoseCheckWindow]);
  }
  // Also when relocalised soon after a loss: frames bridged before it still hold the motion
  // model's extrapolation, which drifts with every frame (extreme_s32 composite: 26 cm after 10),
  // and the lost frames themselves - at most relocalization_attempts of them - get their poses
  // the same way (people filling the view for half a second: 9 bridged + 5 lost frames).
  const bool soon_after_loss = after_loss && lost_frames <= cfg_.tracking.relocalization_attempts;
  // (lost_timestamps_ is empty unless soon after a loss: it keeps no more than that many.)
  if ((gap > 0 || soon_after_loss) && interpolateBridgedRecords(lost_timestamps_)) {
    result.interpolated_lost.insert(result.interpolated_lost.end(), lost_timestamps_.begin(), lost_timestamps_.end());
  }
  lost_timestamps_.clear();
  result.tracked = true;
  result.inliers = matches_inliers_;
  last_frame_ = std::make_unique<Frame>(std::move(frame));
}

bool Tracker::bridgeFrame(Frame& frame, TrackResult& result) {
  const bool expected_to_fail = result.blurred || result.covered;
  const bool bridge =
      expected_to_fail ? gap_frames_ < maxGapFrames() : predicted_frames_ < cfg_.tracking.max_predicted_frames;
  // Right after a map start or a relocalisation there is no velocity yet; a blurred frame then
  // keeps the last pose rather than losing the map.
  if (state_ == TrackingState::Ok && (has_velocity_ || result.blurred) && bridge) {
    // A few untrackable frames in a tracked run (heavy motion blur, a person filling the view):
    // bridge them with the motion model and keep tracking against the last tracked frame, rather
    // than relocalising from scratch. No keyframes come from these frames.
    frame.T_cw = predictPose();
    ++gap_frames_;
    if (!expected_to_fail) ++predicted_frames_;
    const auto& ref = reference_kf_ ? reference_kf_ : last_frame_->reference;
    records_.push_back({frame.timestamp, ref, frame.T_cw * ref->T_wc(), true});
    records_.back().predicted = true;
    result.tracked = true;
    result.predicted = true;
    return true;
  }
  return false;
}

void Tracker::loseFrame(Frame& frame, TrackResult& result) {
  state_ = TrackingState::Lost;
  has_velocity_ = false;
  predicted_frames_ = 0;
  gap_frames_ = 0;
  ++lost_frames_;
  // The frames lost before this one, if a new segment starts on it as soon as relocalisation gives up.
  std::vector<double> lost_before;
  if (lost_frames_ <= cfg_.tracking.relocalization_attempts) {
    lost_timestamps_.push_back(frame.timestamp);
  } else {
    if (lost_frames_ == cfg_.tracking.relocalization_attempts + 1) lost_before.swap(lost_timestamps_);
    lost_timestamps_.clear();  // too long a gap to interpolate across
  }
  temporal_points_.clear();
  if (!localization_only_ && lost_frames_ > cfg_.tracking.relocalization_attempts && !result.blurred &&
      canInitialize(frame)) {
    // Relocalisation keeps failing on a frame good enough to start a map: start a new map segment
    // where the camera was last seen. (On frames too poor to start one - the camera covered, no
    // depth - the old map is kept for relocalisation.)
    frame.T_cw = last_frame_ ? last_frame_->T_cw : Pose::Identity();
    searchRecentKeyFramesOnly();
    spdlog::warn("tracking lost for {} frames; starting a new map segment at frame {}", lost_frames_, frame.id);
    // Re-anchor candidates: this segment's last keyframes, and those of the segment before if
    // this one never found it (a short segment on blurred frames must not hide a long one).
    auto kfs = map_.keyFrames();
    const size_t keep = cfg_.tracking.reanchor_segments ? std::min(kfs.size(), kAnchorCandidates) : 0;
    if (anchor_candidates_.size() > kAnchorCandidates) {
      for (size_t k = kAnchorCandidates; k < anchor_candidates_.size(); ++k) anchor_candidates_[k]->releaseFeatures();
      anchor_candidates_.resize(kAnchorCandidates);
    }
    anchor_candidates_.insert(anchor_candidates_.begin(), kfs.end() - keep, kfs.end());
    anchor_keyframes_left_ = kAnchorAttempts;
    // (initialize() replaces last_frame_: what the gap needs of it is taken first.)
    std::optional<SegmentGap> gap;
    if (last_frame_ && keep > 0 && lost_frames_ == cfg_.tracking.relocalization_attempts + 1) {
      gap = SegmentGap{0, last_frame_->timestamp, kfs[kfs.size() - keep]->id, std::move(lost_before)};
    }
    segment_gap_.reset();
    map_.clearActive(keep);
    if (initialize(frame, true)) {
      result.tracked = true;
      result.new_keyframe = last_kf_;
      result.new_segment = true;
      if (gap) {
        gap->first_record = records_.size() - 1;
        segment_gap_ = std::move(gap);
      }
    }
  }
}

bool Tracker::canInitialize(const Frame& frame) const {
  const auto& F = *frame.features;
  int with_depth = 0, usable = 0;
  for (int i = 0; i < frame.size(); ++i) {
    with_depth += F.hasDepth(i);
    usable += F.hasDepth(i) && !F.excluded[i];
  }
  // As ORB-SLAM2: enough keypoints with depth; of them, those off dynamic objects must still
  // be a fair number (a person may fill most of the first frame).
  return with_depth >= cfg_.tracking.min_init_features && usable >= cfg_.tracking.min_init_features / 5;
}

bool Tracker::initialize(Frame& frame, bool new_segment) {
  if (!canInitialize(frame)) return false;
  const auto& F = *frame.features;
  if (!new_segment) frame.T_cw = Pose::Identity();
  auto kf = std::make_shared<KeyFrame>(map_.newKeyFrameId(), frame.id, frame.timestamp, frame.features, frame.T_cw);
  for (int i = 0; i < frame.size(); ++i) {
    if (!F.hasDepth(i) || F.excluded[i]) continue;
    const Vec3 pw = kf->T_wc() * cam_.unproject(Vec2(F.ideal[i].pt.x, F.ideal[i].pt.y), F.depth[i]);
    auto mp = std::make_shared<MapPoint>(map_.newMapPointId(), pw, kf.get(), F.descriptors.row(i));
    mp->observations[kf.get()] = i;
    kf->addMapPoint(mp, i);
    frame.map_points[i] = mp;
    map_.addMapPoint(mp);
  }
  if (kf->id == 0) kf->not_erase = true;
  map_.addKeyFrame(kf);
  for (auto& mp : kf->map_points) {
    if (mp) mp->updateNormalAndDepth(pyr_);
  }
  frame.reference = kf;
  reference_kf_ = kf;
  last_kf_ = kf;
  local_keyframes_ = {kf};
  local_points_ = map_.mapPoints();
  state_ = TrackingState::Ok;
  lost_frames_ = 0;
  lost_timestamps_.clear();  // a new map: no pose to interpolate from
  has_velocity_ = false;  // the next frame is tracked against this keyframe
  records_.push_back({frame.timestamp, kf, Pose::Identity()});
  last_frame_ = std::make_unique<Frame>(frame);
  spdlog::debug("map initialised at frame {} with {} points", frame.id, map_.mapPointCount());
  return true;
}

void Tracker::updateLastFrame() {
  Frame& last = *last_frame_;
  // The reference keyframe may have been refined by bundle adjustment since. (Records after the
  // last frame's are motion-model predictions.)
  const auto rec = records_.end() - std::min<std::ptrdiff_t>(records_.size(), gap_frames_ + 1);
  if (rec != records_.end() && rec->reference && !rec->reference->bad) {
    last.T_cw = orthonormalized(rec->T_cw());
  }
  if (last_kf_ && last_kf_->frame_id == last.id) return;
  // Localisation only: the map is the reference, and these points are not - nearest first, they are
  // mostly whoever walks in front of the camera. Without them plain ORB localised in fr1_xyz's map
  // within 0.0141 m on all 15 high-dynamic composites; with them 0.025-0.060 m
  // (bench/results/localization_300.md).
  if (localization_only_) return;
  // Temporary points from the last frame's depth help the next frame (as in ORB-SLAM2 RGB-D).
  const auto& F = *last.features;
  std::vector<std::pair<float, int>> by_depth;
  for (int i = 0; i < last.size(); ++i) {
    if (F.hasDepth(i) && !F.excluded[i]) by_depth.emplace_back(F.depth[i], i);
  }
  std::sort(by_depth.begin(), by_depth.end());
  int n = 0;
  const Pose T_wc = last.T_cw.inverse();
  for (const auto& [z, i] : by_depth) {
    const auto& mp = last.map_points[i];
    if (!mp || mp->observations.empty()) {
      const Vec3 pw = T_wc * cam_.unproject(Vec2(F.ideal[i].pt.x, F.ideal[i].pt.y), z);
      auto tmp = std::make_shared<MapPoint>(-1, pw, nullptr, F.descriptors.row(i));
      last.map_points[i] = tmp;
      last.outlier[i] = 0;
      temporal_points_.push_back(tmp);
    }
    ++n;
    if (z > cfg_.depth.close_threshold && n > 100) break;
  }
}

int Tracker::discardOutliers(Frame& frame) {
  int in_map = 0;
  for (int i = 0; i < frame.size(); ++i) {
    auto& mp = frame.map_points[i];
    if (!mp) continue;
    if (frame.outlier[i]) {
      mp->track_in_view = false;
      mp->last_frame_seen = frame.id;
      mp.reset();
      frame.outlier[i] = 0;
    } else if (!mp->observations.empty()) {
      ++in_map;
    }
  }
  return in_map;
}

bool Tracker::trackReferenceKeyFrame(Frame& frame) {
  if (!reference_kf_ || reference_kf_->bad) return false;
  std::vector<std::shared_ptr<MapPoint>> matches;
  const int n = matcher_.searchByDescriptors(*reference_kf_, frame, matches);
  if (n < 15) {
    spdlog::debug("frame {}: reference keyframe {} gave {} matches", frame.id, reference_kf_->id, n);
    return false;
  }
  frame.map_points = matches;
  std::fill(frame.outlier.begin(), frame.outlier.end(), 0);
  frame.T_cw = last_frame_->T_cw;
  optimize::optimizeFramePose(frame, K_, pyr_);
  const int in_map = discardOutliers(frame);
  spdlog::debug("frame {}: reference keyframe {} gave {} matches, {} inliers", frame.id, reference_kf_->id, n, in_map);
  return in_map >= 10;
}

bool Tracker::trackWithMotionModel(Frame& frame) {
  updateLastFrame();
  frame.T_cw = predictPose();
  std::fill(frame.map_points.begin(), frame.map_points.end(), nullptr);
  const float th = 15.0f;
  int n = matcher_.searchByProjection(frame, *last_frame_, th);
  if (n < 20) {
    std::fill(frame.map_points.begin(), frame.map_points.end(), nullptr);
    n = matcher_.searchByProjection(frame, *last_frame_, 2 * th);
  }
  if (n < 20) {
    spdlog::debug("frame {}: motion model found {} matches", frame.id, n);
    return false;
  }
  std::fill(frame.outlier.begin(), frame.outlier.end(), 0);
  optimize::optimizeFramePose(frame, K_, pyr_);
  const int in_map = discardOutliers(frame);
  spdlog::debug("frame {}: motion model {} matches, {} in map after optimisation", frame.id, n, in_map);
  return in_map >= 10;
}

bool Tracker::looksBlurred(double s) const {
  if (cfg_.tracking.blur_ratio <= 0 || s < 0 || recent_sharpness_.empty()) return false;
  std::vector<double> sorted(recent_sharpness_.begin(), recent_sharpness_.end());
  std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
  return s < cfg_.tracking.blur_ratio * sorted[sorted.size() / 2];
}

bool Tracker::checkBlurred(const Frame& frame) {
  const double s = frame.features->sharpness;
  if (cfg_.tracking.blur_ratio <= 0 || s < 0) return false;
  bool blurred = looksBlurred(s);
  // The yardstick is the sharp frames only (blur comes in runs); a long run of "blurred" frames
  // means the scene itself changed, and the yardstick starts again.
  blurred_run_ = blurred ? blurred_run_ + 1 : 0;
  if (blurred_run_ > int(kSharpnessWindow)) {
    recent_sharpness_.clear();
    blurred_run_ = 0;
    blurred = false;
  }
  if (!blurred) {
    recent_sharpness_.push_back(s);
    if (recent_sharpness_.size() > kSharpnessWindow) recent_sharpness_.pop_front();
  }
  return blurred;
}

Pose Tracker::predictPose() const {
  Pose T = last_frame_->T_cw;
  if (!has_velocity_) return T;
  for (int k = 0; k <= gap_frames_; ++k) T = velocity_ * T;
  return orthonormalized(T);
}

bool Tracker::interpolateBridgedRecords(const std::vector<double>& lost) {
  if (!last_frame_) return false;  // (the first frame in a loaded map)
  return interpolateRecordsBefore(records_, records_.size() - 1, last_frame_->timestamp, lost);
}

int Tracker::interpolateAgainInFinalMap() {
  std::lock_guard<std::mutex> lock(map_.mutex());
  return interpolateAgain(records_);
}

int Tracker::extrapolateEndAgainInFinalMap() {
  std::lock_guard<std::mutex> lock(map_.mutex());
  return extrapolateEnd(records_, cfg_.camera.fps, kEndSteps);
}

int Tracker::interpolateExcursions() {
  std::lock_guard<std::mutex> lock(map_.mutex());
  const int posed = tracking::interpolateExcursions(records_, cfg_.tracking.excursion_m, cfg_.camera.fps,
                                                    kExcursionFrames);
  if (posed > 0) spdlog::info("excursion check: {} frame pose(s) interpolated between the frames either side", posed);
  return posed;
}

int Tracker::checkPosesAgainstMap() {
  std::lock_guard<std::mutex> lock(map_.mutex());
  int replaced = 0;
  for (auto& r : records_) replaced += checkRecordPose(r);
  if (replaced > 0) {
    spdlog::info("pose check: {} frame pose(s) replaced by the one their matches give in the final map", replaced);
  }
  return replaced;
}

bool Tracker::checkRecordPose(FrameRecord& record) {
  const auto matches = std::move(record.matches);
  record.matches = {};
  if (matches.empty() || !record.reference || record.reference->bad) return false;
  std::vector<optimize::PoseObservation> obs;
  for (const auto& m : matches) {
    auto mp = m.point.lock();
    while (mp && mp->replaced_by) mp = mp->replaced_by;
    if (!mp || mp->bad) continue;
    obs.push_back({mp->pos_w, Vec2(m.u, m.v), m.u_right, pyr_.inv_sigma2[m.octave]});
  }
  // Only where enough of the frame's points are still in the map (local mapping culls many young
  // ones) and most of them agree on a pose; else the frame keeps the pose it was tracked with.
  const int min_inliers = std::max<int>(cfg_.tracking.min_tracked_inliers, int(obs.size() / 2));
  if (int(obs.size()) < min_inliers) return false;
  const Pose stored = record.T_cw();
  Pose T = stored;
  std::vector<char> outlier;
  if (optimize::optimizePose(obs, K_, T, outlier) < min_inliers) return false;
  // Small differences are the usual spread between a frame's own pose and its keyframe's: the stored
  // pose stays (replacing every pose made fr1_xyz worse, 0.0107 -> 0.0110 m).
  if ((T.inverse().translation() - stored.inverse().translation()).norm() < cfg_.tracking.pose_check_m) return false;
  record.T_cr = orthonormalized(T * record.reference->T_wc());
  return true;
}

bool Tracker::poseJumped(const Pose& T_cw, int periods) const {
  const auto [metres, deg] = poseGap(T_cw, predictPose());
  const auto& t = cfg_.tracking;
  const bool jumped = (t.max_jump_deg > 0 && deg > periods * t.max_jump_deg) ||
                      (t.max_jump_m > 0 && metres > periods * t.max_jump_m);
  if (jumped) spdlog::debug("pose jumped {:.1f} deg / {:.3f} m from the motion model: not used", deg, metres);
  return jumped;
}

void Tracker::updateLocalMap(Frame& frame) {
  // Keyframes that see the frame's points vote; the most voted becomes the reference.
  std::map<KeyFrame*, int, data::KeyFrameIdLess> votes;
  for (int i = 0; i < frame.size(); ++i) {
    const auto& mp = frame.map_points[i];
    if (!mp || mp->bad) continue;
    for (const auto& [kf, idx] : mp->observations) votes[kf]++;
  }
  if (votes.empty()) return;
  local_keyframes_.clear();
  int best = 0;
  KeyFrame* best_kf = nullptr;
  for (const auto& [kf, n] : votes) {
    if (kf->bad) continue;
    if (n > best) {
      best = n;
      best_kf = kf;
    }
    local_keyframes_.push_back(map_.keyFrame(kf->id));
    kf->track_reference_for = frame.id;
  }
  // Neighbours of those: best covisibles, children and parent (up to 80 keyframes).
  const size_t direct = local_keyframes_.size();
  for (size_t k = 0; k < direct && local_keyframes_.size() < 80; ++k) {
    KeyFrame* kf = local_keyframes_[k].get();
    auto add = [&](KeyFrame* n) {
      if (!n || n->bad || n->track_reference_for == frame.id) return false;
      n->track_reference_for = frame.id;
      local_keyframes_.push_back(map_.keyFrame(n->id));
      return true;
    };
    for (KeyFrame* n : kf->bestCovisibles(10)) {
      if (add(n)) break;
    }
    for (KeyFrame* n : kf->children) {
      if (add(n)) break;
    }
    add(kf->parent);
  }
  if (best_kf) {
    reference_kf_ = map_.keyFrame(best_kf->id);
    frame.reference = reference_kf_;
  }
  local_points_.clear();
  for (const auto& kf : local_keyframes_) {
    for (const auto& mp : kf->map_points) {
      if (!mp || mp->bad || mp->local_map_frame == frame.id) continue;
      mp->local_map_frame = frame.id;
      local_points_.push_back(mp);
    }
  }
}

int Tracker::searchLocalPoints(Frame& frame) {
  for (auto& mp : frame.map_points) {
    if (!mp) continue;
    if (mp->bad) {
      mp.reset();
      continue;
    }
    mp->visible++;
    mp->last_frame_seen = frame.id;
    mp->track_in_view = false;
  }
  int to_match = 0;
  for (const auto& mp : local_points_) {
    if (mp->last_frame_seen == frame.id || mp->bad) continue;
    if (matcher_.isInFrustum(*mp, frame.T_cw, 0.5)) {
      mp->visible++;
      ++to_match;
    }
  }
  if (to_match == 0) return 0;
  const float th = frame.id < last_reloc_frame_ + 2 ? 5.0f : 3.0f;
  return matcher_.searchByProjection(frame, local_points_, th);
}

bool Tracker::trackLocalMap(Frame& frame) {
  updateLocalMap(frame);
  searchLocalPoints(frame);
  optimize::optimizeFramePose(frame, K_, pyr_);
  matches_inliers_ = 0;
  for (int i = 0; i < frame.size(); ++i) {
    const auto& mp = frame.map_points[i];
    if (!mp) continue;
    if (!frame.outlier[i]) {
      mp->found++;
      if (!mp->observations.empty()) ++matches_inliers_;
    }
  }
  const int needed = frame.id < last_reloc_frame_ + cfg_.camera.fps ? 50 : cfg_.tracking.min_tracked_inliers;
  spdlog::debug("frame {}: local map {} points, {} inliers (need {})", frame.id, local_points_.size(),
                matches_inliers_, needed);
  return matches_inliers_ >= needed;
}

bool Tracker::needNewKeyFrame(const Frame& frame, bool mapper_idle, int mapper_queue) const {
  const int max_frames = cfg_.tracking.max_frames_between_keyframes > 0 ? cfg_.tracking.max_frames_between_keyframes
                                                                        : int(cfg_.camera.fps);
  const int n_kfs = int(map_.keyFrameCount());
  if (frame.id < last_reloc_frame_ + max_frames && n_kfs > max_frames) return false;
  const int min_obs = n_kfs <= 2 ? 2 : 3;
  const int ref_matches = reference_kf_->trackedMapPoints(min_obs);
  const auto& F = *frame.features;
  int tracked_close = 0, untracked_close = 0;
  for (int i = 0; i < frame.size(); ++i) {
    if (F.depth[i] > 0 && F.depth[i] < cfg_.depth.close_threshold) {
      if (frame.map_points[i] && !frame.outlier[i]) ++tracked_close;
      else ++untracked_close;
    }
  }
  const bool need_close = tracked_close < 100 && untracked_close > 70;
  const double ref_ratio = n_kfs < 2 ? 0.4 : 0.75;
  const bool c1a = frame.id >= last_kf_->frame_id + max_frames;
  const bool c1b = mapper_idle;
  const bool c1c = matches_inliers_ < ref_matches * 0.25 || need_close;
  const bool c2 = (matches_inliers_ < ref_matches * ref_ratio || need_close) && matches_inliers_ > 15;
  if (!((c1a || c1b || c1c) && c2)) return false;
  return mapper_idle || mapper_queue < 3;
}

std::shared_ptr<KeyFrame> Tracker::createKeyFrame(Frame& frame) {
  auto kf = std::make_shared<KeyFrame>(map_.newKeyFrameId(), frame.id, frame.timestamp, frame.features, frame.T_cw);
  const auto& F = *frame.features;
  // Matched map points become observations of the new keyframe.
  for (int i = 0; i < frame.size(); ++i) {
    const auto& mp = frame.map_points[i];
    if (!mp || mp->bad || mp->observations.count(kf.get())) continue;
    kf->addMapPoint(mp, i);
    mp->observations[kf.get()] = i;
  }
  // New points from depth, nearest first: all close ones, at least 100.
  std::vector<std::pair<float, int>> by_depth;
  for (int i = 0; i < frame.size(); ++i) {
    if (F.hasDepth(i) && !F.excluded[i]) by_depth.emplace_back(F.depth[i], i);
  }
  std::sort(by_depth.begin(), by_depth.end());
  int n = 0;
  for (const auto& [z, i] : by_depth) {
    if (!kf->map_points[i]) {
      const Vec3 pw = kf->T_wc() * cam_.unproject(Vec2(F.ideal[i].pt.x, F.ideal[i].pt.y), z);
      auto mp = std::make_shared<MapPoint>(map_.newMapPointId(), pw, kf.get(), F.descriptors.row(i));
      mp->observations[kf.get()] = i;
      kf->addMapPoint(mp, i);
      frame.map_points[i] = mp;
      frame.outlier[i] = 0;
      map_.addMapPoint(mp);
      mp->updateNormalAndDepth(pyr_);
    }
    ++n;
    if (z > cfg_.depth.close_threshold && n > 100) break;
  }
  map_.addKeyFrame(kf);
  kf->updateConnections();
  reference_kf_ = kf;
  last_kf_ = kf;
  frame.reference = kf;
  return kf;
}

void Tracker::startInLoadedMap(bool localization_only) {
  state_ = TrackingState::Lost;
  relocalize_in_whole_map_ = true;
  localization_only_ = localization_only;
  loaded_places_ = place::KeyFrameDatabase();
  if (cfg_.tracking.relocalization_candidates == 0) return;
  const auto t0 = std::chrono::steady_clock::now();
  // Without descriptors nothing is indexed: every keyframe is tried, as without an index.
  if (!loaded_places_.update(place::entriesOf(map_.keyFrames()))) return;
  spdlog::info("loaded map: {} keyframes indexed for relocalisation ({} words) in {:.0f} ms", loaded_places_.size(),
               loaded_places_.words(), msSince(t0));
}

void Tracker::searchRecentKeyFramesOnly() {
  relocalize_in_whole_map_ = false;
  loaded_places_ = place::KeyFrameDatabase();  // its keyframes are not searched any more: let the index go
}

std::vector<std::shared_ptr<KeyFrame>> Tracker::relocalizationCandidates(const Frame& frame) const {
  auto kfs = map_.keyFrames();
  std::vector<std::shared_ptr<KeyFrame>> out;
  if (loaded_places_.trained() && relocalize_in_whole_map_) {
    for (const long id : loaded_places_.mostSimilar(*frame.features, size_t(cfg_.tracking.relocalization_candidates))) {
      const auto kf = map_.keyFrame(id);
      if (kf && !kf->bad) out.push_back(kf);
    }
    // Keyframes made since the map was loaded are not in the index: newest first after it.
    const long newest_loaded = loaded_places_.newestId();
    for (size_t k = kfs.size(); k-- > 0 && kfs[k]->id > newest_loaded;) out.push_back(kfs[k]);
    return out;
  }
  // The most recent keyframes of the active map (all of a loaded one, newest first).
  const size_t first = kfs.size() > 30 && !relocalize_in_whole_map_ ? kfs.size() - 30 : 0;
  for (size_t k = kfs.size(); k-- > first;) out.push_back(kfs[k]);
  return out;
}

bool Tracker::relocalize(Frame& frame) {
  for (const auto& kf : relocalizationCandidates(frame)) {
    std::vector<std::shared_ptr<MapPoint>> matches;
    if (matcher_.searchByDescriptors(*kf, frame, matches) < 15) continue;
    Pose T;
    if (optimize::solvePnpRansac(frame, cam_, matches, T) < 15) continue;
    frame.T_cw = T;
    frame.map_points = matches;
    std::fill(frame.outlier.begin(), frame.outlier.end(), 0);
    if (optimize::optimizeFramePose(frame, K_, pyr_) < 10) continue;
    const int inliers = discardOutliers(frame);
    if (inliers < 15) continue;
    reference_kf_ = kf;
    if (!last_kf_) last_kf_ = kf;
    // (Localisation only: the map is the loaded one, and all of it stays the place to look.)
    if (!localization_only_) searchRecentKeyFramesOnly();
    last_reloc_frame_ = frame.id;
    spdlog::info("relocalised at frame {} against keyframe {} ({} inliers)", frame.id, kf->id, inliers);
    return true;
  }
  return false;
}

bool Tracker::reanchorSegment(Frame& frame, std::vector<double>& interpolated_lost) {
  // Nearest first: the new segment starts where the camera was last seen, so it is roughly in
  // the previous segment's frame already.
  const Vec3 c = frame.centre();
  auto candidates = anchor_candidates_;
  std::stable_sort(candidates.begin(), candidates.end(), [&](const auto& a, const auto& b) {
    return (a->centre() - c).squaredNorm() < (b->centre() - c).squaredNorm();
  });
  // The nearest ones, and one more in turn: the nearest may be blurred, or from a short segment
  // that never got going; the turn reaches every candidate within a few keyframes.
  if (candidates.size() > kAnchorTries) {
    std::swap(candidates[kAnchorTries - 1],
              candidates[kAnchorTries - 1 + anchor_turn_++ % (candidates.size() - kAnchorTries + 1)]);
    candidates.resize(kAnchorTries);
  }
  for (const auto& old : candidates) {
    // The old keyframe's keypoints with depth, as 3-D points in the previous segment's frame.
    const auto& F = *old->features;
    KeyFrame probe_kf(-1, old->frame_id, old->timestamp, old->features, old->T_cw());
    probe_kf.map_points.resize(F.size());
    for (int i = 0; i < F.size(); ++i) {
      if (!F.hasDepth(i) || F.excluded[i]) continue;
      const Vec3 pw = old->T_wc() * cam_.unproject(Vec2(F.ideal[i].pt.x, F.ideal[i].pt.y), F.depth[i]);
      probe_kf.map_points[i] = std::make_shared<MapPoint>(-1, pw, nullptr, F.descriptors.row(i));
    }
    std::vector<std::shared_ptr<MapPoint>> matches;
    const int n = matcher_.searchByDescriptors(probe_kf, frame, matches);
    Pose T_cw_old = Pose::Identity();  // the frame's pose in the previous segment's world
    const int pnp = n < kAnchorMinInliers ? 0 : optimize::solvePnpRansac(frame, cam_, matches, T_cw_old);
    int inliers = 0;
    if (pnp >= kAnchorMinInliers) {
      Frame probe = frame;  // the pose optimisation works on a frame's matches
      probe.T_cw = T_cw_old;
      probe.map_points = matches;
      std::fill(probe.outlier.begin(), probe.outlier.end(), 0);
      inliers = optimize::optimizeFramePose(probe, K_, pyr_);
      T_cw_old = probe.T_cw;
    }
    spdlog::debug("frame {}: re-anchoring to keyframe {}: {} matches, {} PnP inliers, {} after optimisation", frame.id,
                  old->id, n, pnp, inliers);
    if (inliers < kAnchorMinInliers) continue;
    // T_old_new maps the new segment's world into the previous one's.
    const Pose T_old_new = orthonormalized(T_cw_old.inverse() * frame.T_cw);
    map_.transformActive(T_old_new);
    frame.T_cw = orthonormalized(frame.T_cw * T_old_new.inverse());
    last_frame_->T_cw = orthonormalized(last_frame_->T_cw * T_old_new.inverse());
    spdlog::info("frame {}: map segment re-anchored to keyframe {} of the previous one ({} inliers, moved {:.3f} m)",
                 frame.id, old->id, inliers, T_old_new.translation().norm());
    poseFramesLostBeforeSegment(*old, interpolated_lost);
    releaseAnchor();
    return true;
  }
  if (--anchor_keyframes_left_ <= 0) releaseAnchor();
  return false;
}

void Tracker::releaseAnchor() {
  for (auto& kf : anchor_candidates_) kf->releaseFeatures();
  anchor_candidates_.clear();
  segment_gap_.reset();
}

void Tracker::poseFramesLostBeforeSegment(const KeyFrame& anchor, std::vector<double>& interpolated_lost) {
  // Only when anchored to the segment just before: an older one's frame is not the frame the
  // records before this segment are in.
  if (!segment_gap_ || anchor.id < segment_gap_->previous_segment_kf) return;
  const SegmentGap& g = *segment_gap_;
  if (!interpolateRecordsBefore(records_, g.first_record, g.last_tracked, g.lost)) return;
  spdlog::debug("{} frames lost before the segment started posed between the segments' frames", g.lost.size());
  interpolated_lost.insert(interpolated_lost.end(), g.lost.begin(), g.lost.end());
}

}  // namespace tkgslam::tracking
