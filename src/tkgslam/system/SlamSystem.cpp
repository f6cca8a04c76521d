#include "tkgslam/system/SlamSystem.h"

#include <chrono>
#include <mutex>
#include <stdexcept>

#include <opencv2/core/utility.hpp>

#include "tkgslam/common/Elapsed.h"
#include "tkgslam/common/Error.h"
#include "tkgslam/dynamic/DynamicFilter.h"
#include "tkgslam/feature/ImageSharpness.h"
#include "tkgslam/io/MapFile.h"
#include "tkgslam/system/FrameInput.h"

namespace tkgslam {

SlamSystem::SlamSystem(const SlamConfig& config)
    : config_(config), camera_(config.camera), extractor_(config.orb) {
  if (config_.opencv_threads > 0) cv::setNumThreads(config_.opencv_threads);
  if (config_.dynamic.mode != DynamicMode::Orb) {
    boxes_ = std::make_unique<dynamic::BoxPipeline>(
        config_.dynamic.detector, config_.dynamic.tracker,
        dynamic::BoxScheduleParams{config_.dynamic.detect_every, config_.dynamic.detector_latency,
                                   config_.dynamic.usesKalman(), config_.dynamic.usesBoxFlow(),
                                   config_.dynamic.usesLookahead(), config_.dynamic.usesTiles()});
  }
  tracker_ = std::make_unique<tracking::Tracker>(map_, camera_, extractor_.pyramid(), config_);
  mapper_ = std::make_unique<mapping::LocalMapper>(map_, camera_, extractor_.pyramid(), config_);
  if (config_.loop.enabled) {
    loop_closer_ = std::make_unique<loop::LoopCloser>(map_, camera_, extractor_.pyramid(), config_);
  }
  mapping_thread_ =
      std::make_unique<mapping::LocalMappingThread>(*mapper_, loop_closer_.get(), config_.deterministic);
}

SlamSystem::~SlamSystem() { mapping_thread_->stop(); }

void SlamSystem::refillOutsideBoxes(PreparedFrame& frame, const cv::Mat& box_mask) {
  const auto t0 = std::chrono::steady_clock::now();
  auto& features = frame.features;
  const feature::OrbFeatures first{features->raw, features->descriptors};
  // prepare() kept the detections: dynamic modes with the refill on.
  feature::OrbFeatures outside = extractor_.extractAgain(*frame.detections, frame.images.gray, box_mask, first);
  feature::OrbFeatures merged;
  std::vector<cv::Mat> rows;
  for (int i = 0; i < features->size(); ++i) {
    if (!dynamic::inMask(box_mask, features->raw[i].pt)) continue;
    merged.keypoints.push_back(features->raw[i]);
    rows.push_back(features->descriptors.row(i));
  }
  merged.keypoints.insert(merged.keypoints.end(), outside.keypoints.begin(), outside.keypoints.end());
  rows.push_back(outside.descriptors);
  cv::vconcat(rows, merged.descriptors);
  const double sharpness = features->sharpness;
  features = data::makeFrameFeatures(std::move(merged), frame.images.bgr, frame.images.depth_m, camera_, config_.depth);
  features->sharpness = sharpness;
  timing_.add("refill", msSince(t0));
}

tracking::RefineKeypoints SlamSystem::filterDynamic(PreparedFrame& frame, dynamic::BoxMask& box_mask,
                                                    DynamicFrameInfo& info) {
  const io::RgbdImages& images = frame.images;
  const auto t0 = std::chrono::steady_clock::now();
  // T is the boxes' share also with the object mask (dynamicMask): with the mask's own share,
  // TKG on very_high got 0.0868 m instead of 0.0143 m (object_behind 0.3).
  box_mask = dynamic::dynamicMask(info.boxes, images.bgr, images.depth_m, config_.dynamic.box_margin,
                                  config_.dynamic.object_mask ? &config_.dynamic.object : nullptr);
  if (config_.dynamic.object_mask) timing_.add("object_mask", msSince(t0));
  info.box_ratio = box_mask.ratio;
  for (const auto& b : info.boxes) (b.predicted ? info.predicted : info.detected)++;
  const double refill = config_.dynamic.refill_ratio;
  // (Not on a motion-blurred image: more keypoints there are more smeared ones.)
  if (refill > 0 && box_mask.ratio >= refill && !tracker_->looksBlurred(frame.features->sharpness)) {
    refillOutsideBoxes(frame, box_mask.mask);
  }
  frame.detections.reset();
  auto& features = frame.features;
  dynamic::excludeKeypointsInMask(*features, box_mask.mask);
  if (!config_.dynamic.usesGeometry()) return {};
  const auto& gp = config_.dynamic.geometry;
  // Boxes cover most of the image: the multi-view geometry check re-admits the static keypoints
  // inside them. On every frame: the same check outside the boxes finds movers the detector missed.
  const bool in_boxes = box_mask.ratio >= gp.ratio_threshold;
  if (!in_boxes && !gp.unboxed_check) return {};
  // Runs once tracking has a pose; returns how many keypoints changed side.
  return [this, &gp, &images, &box_mask, &info, in_boxes](data::Frame& frame,
                                                          const std::vector<std::shared_ptr<data::KeyFrame>>& local) {
    const auto tg = std::chrono::steady_clock::now();
    std::vector<Pose> poses;
    std::vector<const data::KeyFrame*> kfs;
    for (const auto& kf : local) {
      if (kf->bad) continue;
      poses.push_back(kf->T_cw());
      kfs.push_back(kf.get());
    }
    std::vector<dynamic::ReferenceView> refs;
    for (int i : dynamic::selectReferenceViews(frame.T_cw, poses, gp.reference_keyframes)) {
      refs.push_back({kfs[i]->T_cw(), kfs[i]->features});
    }
    if (in_boxes) {
      const auto g = dynamic::checkMultiViewGeometry(frame.T_cw, images.depth_m, box_mask.mask, refs, camera_, gp);
      info.readmitted = dynamic::readmitStaticKeypoints(*frame.features, box_mask.mask, g.dynamic_region, images.depth_m, gp);
      info.geometry = true;
    }
    if (gp.unboxed_check) {
      const auto u = dynamic::findUnboxedMovers(frame.T_cw, images.depth_m, box_mask.mask, refs, camera_, gp);
      info.unboxed = dynamic::excludeKeypointsInMask(*frame.features, u.dynamic_region);
    }
    timing_.add("geometry", msSince(tg));
    return info.readmitted + info.unboxed;
  };
}

void SlamSystem::recordBoxTimings(const dynamic::BoxTimings& bt) {
  if (bt.detector_ms >= 0) timing_.add("detector", bt.detector_ms);
  timing_.add("detector_wait", bt.wait_ms);
  if (config_.dynamic.usesKalman()) timing_.add("box_tracker", bt.tracker_ms);
}

int SlamSystem::cullLateDynamicPoints(const std::vector<dynamic::FrameBoxes>& late, cv::Size image) {
  if (late.empty()) return 0;
  const auto t0 = std::chrono::steady_clock::now();
  int erased = 0;
  std::lock_guard<std::mutex> lock(map_.mutex());
  for (const auto& kf : map_.keyFrames()) {
    if (!kf->features || kf->frame_id < late.front().first || kf->frame_id > late.back().first) continue;
    const auto& boxes = late[size_t(kf->frame_id - late.front().first)].second;
    if (boxes.empty()) continue;
    const cv::Mat mask = dynamic::rasterizeBoxes(boxes, image, config_.dynamic.box_margin).mask;
    for (size_t i = 0; i < kf->map_points.size(); ++i) {
      const auto mp = kf->map_points[i];  // a copy: erasing resets the slot
      // Only points this keyframe created: older ones were mapped before the people arrived.
      if (!mp || mp->bad || mp->first_keyframe_id != kf->id) continue;
      const cv::Point p(cvRound(kf->features->raw[i].pt.x), cvRound(kf->features->raw[i].pt.y));
      if (p.inside(cv::Rect(0, 0, mask.cols, mask.rows)) && mask.at<uchar>(p)) {
        map_.eraseMapPoint(mp.get());
        ++erased;
      }
    }
  }
  timing_.add("late_culling", msSince(t0));
  return erased;
}

int SlamSystem::scoreAgainstTruth(const cv::Mat& truth, const data::FrameFeatures& features) {
  ++classification_.frames;
  const long missed_before = classification_.false_negative;
  const cv::Rect image(0, 0, truth.cols, truth.rows);
  for (int i = 0; i < features.size(); ++i) {
    const cv::Point p(cvRound(features.raw[i].pt.x), cvRound(features.raw[i].pt.y));
    const bool truly = p.inside(image) && truth.at<uchar>(p) > 0;
    const bool dropped = features.excluded[i];
    (truly ? (dropped ? classification_.true_positive : classification_.false_negative)
           : (dropped ? classification_.false_positive : classification_.true_negative))++;
  }
  return int(classification_.false_negative - missed_before);
}

SlamSystem::PreparedFrame SlamSystem::prepare(const io::RgbdImages& images) {
  const auto t0 = std::chrono::steady_clock::now();
  PreparedFrame f;
  f.index = frames_++;
  f.images = images;
  // A scheduled detection runs on its own thread while this one extracts ORB features.
  if (boxes_) {
    boxes_->beginFrame(f.index, images.bgr, images.depth_m, images.gray);
    if (config_.dynamic.late_culling) f.late_culled = cullLateDynamicPoints(boxes_->takeLateBoxes(), images.bgr.size());
  }
  // Timed on its own: beginFrame may wait for the detector (lookahead), which is detector_wait.
  const auto t_orb = std::chrono::steady_clock::now();
  // Dynamic modes keep the pyramid and FAST corners: boxes over much of the image get the
  // keypoints redistributed outside them from these (filterDynamic).
  if (boxes_ && config_.dynamic.refill_ratio > 0) f.detections = std::make_unique<feature::OrbDetections>();
  auto orb = extractor_.extract(images.gray, {}, f.detections.get());
  f.features = data::makeFrameFeatures(std::move(orb), images.bgr, images.depth_m, camera_, config_.depth);
  if (config_.tracking.blur_ratio > 0) f.features->sharpness = feature::imageSharpness(images.gray);
  f.orb_ms = msSince(t_orb);
  f.prepare_ms = msSince(t0);
  timing_.add("orb_extraction", f.orb_ms);
  return f;
}

FrameOutcome SlamSystem::track(PreparedFrame& prepared, std::vector<dynamic::Detection> boxes) {
  const auto t0 = std::chrono::steady_clock::now();
  const io::RgbdImages& images = prepared.images;
  auto& features = prepared.features;
  dynamic::BoxMask box_mask;
  DynamicFrameInfo info;
  info.late_culled = prepared.late_culled;
  info.boxes = std::move(boxes);
  tracking::RefineKeypoints refine;
  if (boxes_) refine = filterDynamic(prepared, box_mask, info);

  const auto t1 = std::chrono::steady_clock::now();
  data::Frame frame(prepared.index, images.timestamp, features);
  frame.box_cover = box_mask.ratio;
  FrameOutcome outcome;
  outcome.index = prepared.index;
  outcome.timestamp = images.timestamp;
  outcome.result = tracker_->track(std::move(frame), mapping_thread_->idle(), mapping_thread_->queued(), refine);
  outcome.state = tracker_->state();
  const double t_track = msSince(t1);

  if (!images.truth_mask.empty()) info.missed_dynamic = scoreAgainstTruth(images.truth_mask, *features);
  if (boxes_) {
    info.timestamp = images.timestamp;
    info.keypoints = features->size();
    for (int i = 0; i < features->size(); ++i) {
      if (!features->excluded[i]) continue;
      ++info.dropped;
      info.dropped_points.push_back(features->raw[i].pt);
    }
    dynamic_info_.push_back(std::move(info));
  }

  const auto t2 = std::chrono::steady_clock::now();
  if (outcome.result.new_keyframe) mapping_thread_->insert(outcome.result.new_keyframe);
  const double t_map = msSince(t2);  // non-zero only when mapping runs synchronously

  timing_.add("tracking", t_track);
  timing_.add("orb_and_tracking", prepared.orb_ms + t_track);
  if (config_.deterministic) timing_.add("local_mapping_sync", t_map);
  timing_.add("total", prepared.prepare_ms + prepared.wait_ms + msSince(t0));
  return outcome;
}

void SlamSystem::trackHeld(std::vector<dynamic::FrameBoxes> final_boxes, long through,
                           std::vector<FrameOutcome>& out) {
  auto next = held_.begin();
  for (auto& [index, boxes] : final_boxes) {
    while (next != held_.end() && next->boxes) ++next;
    if (next == held_.end() || next->index != index) {
      throw std::logic_error("lookahead: boxes for a frame that is not held back");
    }
    next->boxes = std::move(boxes);
  }
  while (!held_.empty() && held_.front().boxes && held_.front().index <= through) {
    out.push_back(track(held_.front(), std::move(*held_.front().boxes)));
    held_.pop_front();
  }
}

std::vector<FrameOutcome> SlamSystem::processFrame(const io::RgbdImages& input) {
  const io::RgbdImages images = checkFrameImages(input, {camera_.width(), camera_.height()}, last_timestamp_);
  last_timestamp_ = images.timestamp;
  PreparedFrame prepared = prepare(images);
  std::vector<FrameOutcome> out;
  dynamic::BoxTimings bt;
  if (boxes_ && boxes_->lookahead()) {
    auto final_boxes = boxes_->takeFinalBoxes(bt);
    recordBoxTimings(bt);
    const long through = prepared.index - config_.dynamic.lookaheadDelay();
    held_.push_back(std::move(prepared));
    trackHeld(std::move(final_boxes), through, out);
    return out;
  }
  std::vector<dynamic::Detection> boxes;
  if (boxes_) {
    const auto tb = std::chrono::steady_clock::now();
    boxes = boxes_->frameBoxes(images.bgr.size(), bt);  // waits for a synchronous detection
    recordBoxTimings(bt);
    prepared.wait_ms = msSince(tb);
  }
  out.push_back(track(prepared, std::move(boxes)));
  return out;
}

std::vector<FrameOutcome> SlamSystem::finish() {
  std::vector<FrameOutcome> out;
  if (boxes_ && boxes_->lookahead() && !held_.empty()) {
    dynamic::BoxTimings bt;
    auto final_boxes = boxes_->flush(bt);
    recordBoxTimings(bt);
    trackHeld(std::move(final_boxes), held_.back().index, out);
  }
  mapping_thread_->drain();
  if (config_.tracking.pose_check_m > 0) tracker_->checkPosesAgainstMap();
  tracker_->interpolateAgainInFinalMap();
  tracker_->extrapolateEndAgainInFinalMap();
  if (config_.tracking.excursion_m > 0) tracker_->interpolateExcursions();
  return out;
}

size_t SlamSystem::loadMap(const std::string& path, bool localization_only) {
  if (frames_ > 0) throw InputError("a map can only be loaded before the first frame");
  std::lock_guard<std::mutex> lock(map_.mutex());
  const size_t n = io::readMapFile(path, map_, camera_, extractor_.pyramid());
  tracker_->startInLoadedMap(localization_only);
  return n;
}

void SlamSystem::saveMap(const std::string& path) const {
  std::lock_guard<std::mutex> lock(map_.mutex());
  io::writeMapFile(path, map_, camera_, extractor_.pyramid());
}

std::vector<StampedPose> SlamSystem::trajectory() const {
  std::lock_guard<std::mutex> lock(map_.mutex());
  std::vector<StampedPose> out;
  for (const auto& rec : tracker_->records()) out.push_back({rec.timestamp, rec.T_cw().inverse()});
  return out;
}

std::vector<StampedPose> SlamSystem::keyFrameTrajectory() const {
  std::lock_guard<std::mutex> lock(map_.mutex());
  std::vector<StampedPose> out;
  for (const auto& [id, kf] : map_.allKeyFrames()) {
    if (!kf->bad && kf->frame_id >= 0) out.push_back({kf->timestamp, kf->T_wc()});
  }
  return out;
}

std::vector<io::ColouredPoint> SlamSystem::mapPoints() const {
  std::lock_guard<std::mutex> lock(map_.mutex());
  std::vector<io::ColouredPoint> out;
  for (const auto& mp : map_.mapPoints()) {
    io::ColouredPoint p;
    p.position = mp->pos_w;
    if (mp->reference && mp->observations.count(mp->reference)) {
      p.bgr = mp->reference->features->colour[mp->observations.at(mp->reference)];
    }
    out.push_back(p);
  }
  return out;
}

size_t SlamSystem::keyFrameCount() const {
  std::lock_guard<std::mutex> lock(map_.mutex());
  return map_.keyFrameCount();
}

size_t SlamSystem::mapPointCount() const {
  std::lock_guard<std::mutex> lock(map_.mutex());
  return map_.mapPointCount();
}

}  // namespace tkgslam
