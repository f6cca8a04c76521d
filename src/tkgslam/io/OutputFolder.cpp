#include "tkgslam/io/OutputFolder.h"

#include <filesystem>
#include <fstream>
#include <system_error>

#include <fmt/format.h>

#include "tkgslam/common/Error.h"

namespace tkgslam::io {

void createOutputFolder(const std::string& path) {
  std::error_code ec;
  std::filesystem::create_directories(path, ec);
  if (ec) throw InputError(fmt::format("cannot create output folder '{}': {}", path, ec.message()));
  if (!std::filesystem::is_directory(path, ec)) {
    throw InputError(fmt::format("cannot create output folder '{}': a file of that name exists", path));
  }
}

void checkWritableFile(const std::string& path, const std::string& what) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::path p = fs::absolute(path, ec);
  if (fs::is_directory(p, ec)) throw InputError(fmt::format("{} '{}': is a folder, not a file", what, path));
  const fs::path dir = p.parent_path();
  if (!fs::is_directory(dir, ec)) {
    throw InputError(fmt::format("{} '{}': folder '{}' does not exist", what, path, dir.string()));
  }
  const bool existed = fs::exists(p, ec);
  {
    std::ofstream probe(p, std::ios::app);
    if (!probe) throw InputError(fmt::format("{} '{}': cannot write there", what, path));
  }
  if (!existed) fs::remove(p, ec);
}

}  // namespace tkgslam::io
