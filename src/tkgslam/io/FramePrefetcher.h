#pragma once
// Reads a dataset's frames on a background thread, a few frames ahead of the consumer, so that
// decoding the images (12 ms a 640 x 480 frame: two PNGs) overlaps tracking instead of adding to
// it. Frames come out in order, exactly as TumDataset::load gives them: reading is pure, so a
// deterministic run stays deterministic.
#include <condition_variable>
#include <deque>
#include <exception>
#include <mutex>
#include <optional>
#include <thread>

#include "tkgslam/io/TumDataset.h"

namespace tkgslam::io {

class FramePrefetcher {
 public:
  /// One frame as read: its images, or what load() threw for it.
  struct Frame {
    int index = 0;
    /// The images; rethrows load()'s exception for a frame that could not be read (e.g. InputError).
    RgbdImages take();

   private:
    friend class FramePrefetcher;
    RgbdImages images_;
    std::exception_ptr error_;
  };

  /// Starts reading frames [first, end) of `dataset`, which must outlive this object, holding at
  /// most `ahead` (>= 1) frames not yet taken.
  FramePrefetcher(const TumDataset& dataset, int first, int end, int ahead = 2);
  /// Stops reading (a frame being decoded is finished first) and joins the thread.
  ~FramePrefetcher();
  FramePrefetcher(const FramePrefetcher&) = delete;
  FramePrefetcher& operator=(const FramePrefetcher&) = delete;

  /// The next frame in order, waiting for it if it is not read yet; nullopt after frame end - 1.
  std::optional<Frame> next();

 private:
  const TumDataset& dataset_;
  const int end_;
  const size_t ahead_;
  int next_index_;  ///< the next frame next() hands out
  std::mutex mutex_;
  std::condition_variable ready_;  ///< a frame was read
  std::condition_variable room_;   ///< a frame was taken, or stop
  std::deque<Frame> frames_;       ///< read, not yet taken (guarded by mutex_)
  bool stop_ = false;              ///< guarded by mutex_
  std::thread reader_;
};

}  // namespace tkgslam::io
