#pragma once
// Creating the folder a command writes into. A path that cannot be one (an existing file, a place
// without write access) is the user's input, so it is an InputError naming the path and the reason,
// not an internal error.
#include <string>

namespace tkgslam::io {

/// Creates `path` and its parents if missing; throws InputError when that fails.
void createOutputFolder(const std::string& path);

}  // namespace tkgslam::io
