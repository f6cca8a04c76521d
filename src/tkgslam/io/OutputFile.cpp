#include "tkgslam/io/OutputFile.h"

#include <cerrno>
#include <cstring>
#include <filesystem>

#include <fmt/format.h>

#include "tkgslam/common/Error.h"

namespace tkgslam::io {
namespace {

InputError writeError(const std::string& what, const std::string& path, int error) {
  return InputError(fmt::format("cannot write {} '{}': {}", what, path,
                                error == EISDIR ? "it is a folder" : std::strerror(error)));
}

/// Writes `content` to the file `path`; returns 0 or the errno of the first failure.
int writeWhole(const std::string& path, std::string_view content) {
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (!f) return errno;
  int error = 0;
  if (std::fwrite(content.data(), 1, content.size(), f) != content.size() || std::fflush(f) != 0) error = errno;
  if (std::fclose(f) != 0 && error == 0) error = errno;
  return error;
}

}  // namespace

void writeOutputFile(const std::string& path, const std::string& what, std::string_view content) {
  std::error_code ec;
  const auto status = std::filesystem::status(path, ec);
  if (std::filesystem::is_directory(status)) throw writeError(what, path, EISDIR);
  const bool exists = std::filesystem::exists(status);
  if (exists && !std::filesystem::is_regular_file(status)) {
    if (const int error = writeWhole(path, content)) throw writeError(what, path, error);
    return;
  }
  const std::string part = path + ".part";
  int error = writeWhole(part, content);
  if (exists && (error == EACCES || error == EPERM)) {
    // A writable file in a folder that is not (what checkWritableFile lets through): in place.
    std::filesystem::remove(part, ec);
    if ((error = writeWhole(path, content)) != 0) throw writeError(what, path, error);
    return;
  }
  if (error == 0 && std::rename(part.c_str(), path.c_str()) != 0) error = errno;
  if (error != 0) {
    std::filesystem::remove(part, ec);
    throw writeError(what, path, error);
  }
}

OutputLog::OutputLog(const std::string& path, const std::string& what)
    : path_(path), what_(what), file_(std::fopen(path.c_str(), "wb")) {
  if (!file_) throw writeError(what_, path_, errno);
}

OutputLog::~OutputLog() {
  if (file_) std::fclose(file_);
}

void OutputLog::write(std::string_view text) {
  if (!file_ || error_ != 0) return;
  if (std::fwrite(text.data(), 1, text.size(), file_) != text.size() || std::fflush(file_) != 0) error_ = errno;
}

void OutputLog::finish() {
  if (file_) {
    if (std::fclose(file_) != 0 && error_ == 0) error_ = errno;
    file_ = nullptr;
  }
  if (error_ != 0) throw writeError(what_, path_, error_);
}

}  // namespace tkgslam::io
