#pragma once
// The CLI's default files (configs/tum_fr1.yaml, ../shared/models/...) are relative to the working
// folder, i.e. they are found when the command runs from the tkgslam folder.
#include <filesystem>
#include <string>

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include "tkgslam/common/Error.h"

namespace tkgslam::app {

/// When `option` was not given and its default file does not exist, throws an InputError that says
/// so (instead of a bare "cannot open" for a path the user never typed).
inline void requireDefaultFile(const CLI::Option& option, const std::string& name) {
  if (option.count() > 0) return;
  const std::string path = option.get_default_str();
  if (std::filesystem::exists(path)) return;
  throw InputError(fmt::format("{} was not given and its default '{}' is not there: it is relative to the working "
                               "folder, so run from the tkgslam folder or give {}",
                               name, path, name));
}

}  // namespace tkgslam::app
