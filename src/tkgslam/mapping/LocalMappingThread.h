#pragma once
// Runs a LocalMapper beside tracking: keyframes are queued by tracking and processed in order on
// a worker thread. In synchronous mode (deterministic runs) each keyframe is processed at once on
// the caller's thread, so results do not depend on thread timing.
#include <condition_variable>
#include <deque>
#include <memory>
#include <mutex>
#include <thread>

#include "tkgslam/loop/LoopCloser.h"
#include "tkgslam/mapping/LocalMapper.h"

namespace tkgslam::mapping {

class LocalMappingThread {
 public:
  /// `loop_closer` (may be null) looks for a loop from each keyframe after local mapping.
  LocalMappingThread(LocalMapper& mapper, loop::LoopCloser* loop_closer, bool synchronous);
  ~LocalMappingThread();
  LocalMappingThread(const LocalMappingThread&) = delete;
  LocalMappingThread& operator=(const LocalMappingThread&) = delete;

  void insert(std::shared_ptr<data::KeyFrame> kf);
  /// True when nothing is queued or being processed.
  bool idle() const;
  int queued() const;
  /// Blocks until every queued keyframe has been processed.
  void drain();
  /// Stops the worker after the queue is drained.
  void stop();

 private:
  void run();
  void processOne(const std::shared_ptr<data::KeyFrame>& kf, bool more_pending);

  LocalMapper& mapper_;
  loop::LoopCloser* loop_closer_;
  const bool synchronous_;
  mutable std::mutex mutex_;
  std::condition_variable cv_;
  std::condition_variable drained_cv_;
  std::deque<std::shared_ptr<data::KeyFrame>> queue_;
  bool busy_ = false;
  bool stopping_ = false;
  std::thread worker_;
};

}  // namespace tkgslam::mapping
