#include "tkgslam/mapping/LocalMappingThread.h"

namespace tkgslam::mapping {

LocalMappingThread::LocalMappingThread(LocalMapper& mapper, loop::LoopCloser* loop_closer, bool synchronous)
    : mapper_(mapper), loop_closer_(loop_closer), synchronous_(synchronous) {
  if (!synchronous_) worker_ = std::thread([this] { run(); });
}

LocalMappingThread::~LocalMappingThread() { stop(); }

void LocalMappingThread::insert(std::shared_ptr<data::KeyFrame> kf) {
  if (synchronous_) {
    processOne(kf, false);
    return;
  }
  {
    std::lock_guard<std::mutex> lock(mutex_);
    queue_.push_back(std::move(kf));
  }
  cv_.notify_one();
}

bool LocalMappingThread::idle() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return queue_.empty() && !busy_;
}

int LocalMappingThread::queued() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return int(queue_.size());
}

void LocalMappingThread::drain() {
  if (synchronous_) return;
  std::unique_lock<std::mutex> lock(mutex_);
  drained_cv_.wait(lock, [this] { return queue_.empty() && !busy_; });
}

void LocalMappingThread::stop() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  cv_.notify_one();
  if (worker_.joinable()) worker_.join();
}

void LocalMappingThread::processOne(const std::shared_ptr<data::KeyFrame>& kf, bool more_pending) {
  mapper_.process(kf, more_pending);
  if (loop_closer_) loop_closer_->process(kf);
}

void LocalMappingThread::run() {
  for (;;) {
    std::shared_ptr<data::KeyFrame> kf;
    bool more = false;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      cv_.wait(lock, [this] { return stopping_ || !queue_.empty(); });
      if (queue_.empty()) return;  // stopping and drained
      kf = std::move(queue_.front());
      queue_.pop_front();
      more = !queue_.empty();
      busy_ = true;
    }
    processOne(kf, more);
    {
      std::lock_guard<std::mutex> lock(mutex_);
      busy_ = false;
    }
    drained_cv_.notify_all();
  }
}

}  // namespace tkgslam::mapping
