#pragma once
// Writing the files the commands produce. An ofstream reports a full disk only on a write that
// finds it: the last buffer goes out when the stream closes, where nothing checks, so a file could
// end short with exit code 0. Every output is written here instead, and a failed write throws.
#include <cstdio>
#include <string>
#include <string_view>

namespace tkgslam::io {

/// Writes `content` to `path`, creating it or replacing an earlier file. A regular file is written
/// to `<path>.part` and renamed when complete, so `path` holds either the earlier file or the whole
/// new one, never a part; a device or pipe (/dev/stdout), and a writable file in a folder that is
/// not, are written directly. Throws InputError
/// "cannot write <what> '<path>': <reason>" (reason e.g. "No space left on device"; `what` e.g.
/// "trajectory file") and leaves no `.part` behind.
void writeOutputFile(const std::string& path, const std::string& what, std::string_view content);

/// A file written piece by piece over a run (a log). Each write goes to disk at once, so the file
/// shows a long run's progress and keeps what was logged if the run dies. The first failed write
/// is kept; finish() reports it.
class OutputLog {
 public:
  /// Creates (truncates) `path`. Throws InputError as writeOutputFile does.
  OutputLog(const std::string& path, const std::string& what);
  ~OutputLog();
  OutputLog(const OutputLog&) = delete;
  OutputLog& operator=(const OutputLog&) = delete;

  void write(std::string_view text);
  /// Closes the file. Throws InputError if any write or the close failed. Idempotent.
  void finish();

 private:
  std::string path_, what_;
  std::FILE* file_ = nullptr;
  int error_ = 0;  ///< errno of the first failure, 0 while none
};

}  // namespace tkgslam::io
