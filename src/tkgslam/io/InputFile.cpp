#include "tkgslam/io/InputFile.h"

#include <filesystem>

#include <fmt/format.h>

#include "tkgslam/common/Error.h"

namespace tkgslam::io {

std::ifstream openInputFile(const std::string& path, const std::string& what, std::ios::openmode mode) {
  std::error_code ec;
  const auto status = std::filesystem::status(path, ec);
  if (!std::filesystem::exists(status)) {
    // A relative path is taken from the working folder (or a config file's): say where that was.
    const std::filesystem::path p(path);
    const std::string where =
        p.is_relative() ? fmt::format(" ({})", std::filesystem::absolute(p).lexically_normal().string()) : "";
    throw InputError(fmt::format("{} '{}'{} does not exist", what, path, where));
  }
  if (std::filesystem::is_directory(status)) {
    throw InputError(fmt::format("{} '{}' is a folder, not a file", what, path));
  }
  std::ifstream in(path, mode);
  if (!in) throw InputError(fmt::format("{} '{}' cannot be read", what, path));
  return in;
}

}  // namespace tkgslam::io
