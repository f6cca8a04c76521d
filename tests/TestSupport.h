#pragma once
// Helpers for tests: skipping when ../shared is absent (SharedData.h locates it), temporary folders,
// running the CLI.
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <random>
#include <string>

#include <gtest/gtest.h>

#include "SharedData.h"
#include "tkgslam/common/Error.h"

namespace tkgslam::test {

#define TKGSLAM_REQUIRE_SHARED()                                                             \
  do {                                                                                       \
    if (::tkgslam::test::sharedDir().empty())                                                \
      GTEST_SKIP() << "../shared (datasets/models) not found next to the repository; skipped"; \
  } while (0)

/// The message of the InputError `fn` throws; empty when it throws none.
inline std::string inputErrorOf(const std::function<void()>& fn) {
  try {
    fn();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

/// A fresh temporary directory, removed when the object dies.
class TempDir {
 public:
  TempDir() {
    std::random_device rd;
    path_ = std::filesystem::temp_directory_path() / ("tkgslam_test_" + std::to_string(rd()) + std::to_string(rd()));
    std::filesystem::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  const std::filesystem::path& path() const { return path_; }
  std::filesystem::path operator/(const std::string& s) const { return path_ / s; }

 private:
  std::filesystem::path path_;
};

/// Whole file as a string (binary-safe); empty if it cannot be read.
inline std::string readFile(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

/// `jpeg` (a whole file) with an APP1 segment holding `payload` (under 64 KiB) after its start marker:
/// where EXIF data and thumbnails go.
inline std::string withApp1Segment(const std::string& jpeg, const std::string& payload) {
  const std::size_t length = payload.size() + 2;  // the length field counts itself
  return jpeg.substr(0, 2) + "\xFF\xE1" + char(length >> 8) + char(length & 0xFF) + payload + jpeg.substr(2);
}

inline void writeText(const std::filesystem::path& p, const std::string& text) {
  std::filesystem::create_directories(p.parent_path());
  std::ofstream(p) << text;
}

/// The part of a markdown text from the heading "### <heading>..." up to the next "### " heading ("" if none).
inline std::string markdownSection(const std::string& text, const std::string& heading) {
  const auto h = text.find("### " + heading);
  if (h == std::string::npos) return "";
  const auto end = text.find("\n### ", h + 4);
  return text.substr(h, end == std::string::npos ? std::string::npos : end - h);
}

/// Runs a shell command; returns its exit code and captures stdout+stderr into `output`.
inline int runCommand(const std::string& command, std::string* output = nullptr) {
  TempDir tmp;
  const auto log = tmp / "out.txt";
  const int status = std::system((command + " > " + log.string() + " 2>&1").c_str());
  if (output) *output = readFile(log);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

/// Runs the CLI with arguments; returns its exit code and captures stdout+stderr into `output`.
inline int runCli(const std::string& args, std::string* output = nullptr) {
  return runCommand(std::string(TKGSLAM_CLI) + " " + args, output);
}

}  // namespace tkgslam::test
