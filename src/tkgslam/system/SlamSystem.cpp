#include "tkgslam/system/SlamSystem.h"

#include <chrono>
#include <mutex>

namespace tkgslam {

namespace {
double msSince(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
}
}  // namespace

SlamSystem::SlamSystem(const SlamConfig& config)
    : config_(config), camera_(config.camera), extractor_(config.orb) {
  tracker_ = std::make_unique<tracking::Tracker>(map_, camera_, extractor_.pyramid(), config_);
  mapper_ = std::make_unique<mapping::LocalMapper>(map_, camera_, extractor_.pyramid(), config_);
  mapping_thread_ = std::make_unique<mapping::LocalMappingThread>(*mapper_, config_.deterministic);
}

SlamSystem::~SlamSystem() { mapping_thread_->stop(); }

tracking::TrackResult SlamSystem::processFrame(const io::RgbdImages& images) {
  const auto t0 = std::chrono::steady_clock::now();
  auto orb = extractor_.extract(images.gray);
  auto features = data::makeFrameFeatures(std::move(orb), images.bgr, images.depth_m, camera_, config_.depth);
  const double t_extract = msSince(t0);

  const auto t1 = std::chrono::steady_clock::now();
  data::Frame frame(frames_, images.timestamp, features);
  auto result = tracker_->track(std::move(frame), mapping_thread_->idle(), mapping_thread_->queued());
  const double t_track = msSince(t1);

  const auto t2 = std::chrono::steady_clock::now();
  if (result.new_keyframe) mapping_thread_->insert(result.new_keyframe);
  const double t_map = msSince(t2);  // non-zero only when mapping runs synchronously

  timing_.add("orb_extraction", t_extract);
  timing_.add("tracking", t_track);
  timing_.add("orb_and_tracking", t_extract + t_track);
  if (config_.deterministic) timing_.add("local_mapping_sync", t_map);
  timing_.add("total", msSince(t0));
  ++frames_;
  return result;
}

void SlamSystem::finish() { mapping_thread_->drain(); }

std::vector<StampedPose> SlamSystem::trajectory() const {
  std::lock_guard<std::mutex> lock(map_.mutex());
  std::vector<StampedPose> out;
  for (const auto& rec : tracker_->records()) {
    const data::KeyFrame* kf = rec.reference.get();
    Pose T = rec.T_cr;
    while (kf->bad && kf->parent) {  // culled reference: follow the spanning tree
      T = T * kf->T_c_parent;
      kf = kf->parent;
    }
    out.push_back({rec.timestamp, (T * kf->T_cw()).inverse()});
  }
  return out;
}

std::vector<StampedPose> SlamSystem::keyFrameTrajectory() const {
  std::lock_guard<std::mutex> lock(map_.mutex());
  std::vector<StampedPose> out;
  for (const auto& [id, kf] : map_.allKeyFrames()) {
    if (!kf->bad) out.push_back({kf->timestamp, kf->T_wc()});
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
