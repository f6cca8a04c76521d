#include "tkgslam/io/FramePrefetcher.h"

#include <algorithm>
#include <utility>

namespace tkgslam::io {

RgbdImages FramePrefetcher::Frame::take() {
  if (error_) std::rethrow_exception(error_);
  return std::move(images_);
}

FramePrefetcher::FramePrefetcher(const TumDataset& dataset, int first, int end, int ahead)
    : dataset_(dataset), end_(std::max(first, end)), ahead_(size_t(std::max(1, ahead))), next_index_(first) {
  reader_ = std::thread([this, first] {
    for (int i = first; i < end_; ++i) {
      {
        std::unique_lock<std::mutex> lock(mutex_);
        room_.wait(lock, [this] { return stop_ || frames_.size() < ahead_; });
        if (stop_) return;
      }
      Frame f;
      f.index = i;
      try {
        f.images_ = dataset_.load(i);
      } catch (...) {
        f.error_ = std::current_exception();
      }
      {
        std::lock_guard<std::mutex> lock(mutex_);
        frames_.push_back(std::move(f));
      }
      ready_.notify_one();
    }
  });
}

FramePrefetcher::~FramePrefetcher() {
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  room_.notify_one();
  reader_.join();
}

std::optional<FramePrefetcher::Frame> FramePrefetcher::next() {
  if (next_index_ >= end_) return std::nullopt;
  std::unique_lock<std::mutex> lock(mutex_);
  ready_.wait(lock, [this] { return !frames_.empty(); });
  Frame f = std::move(frames_.front());
  frames_.pop_front();
  lock.unlock();
  room_.notify_one();
  ++next_index_;
  return f;
}

}  // namespace tkgslam::io
