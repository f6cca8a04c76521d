#include "tkgslam/io/OutputFolder.h"

#include <filesystem>
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

}  // namespace tkgslam::io
