#pragma once
// Creating the folder a command writes into. A path that cannot be one (an existing file, a place
// without write access) is the user's input, so it is an InputError naming the path and the reason,
// not an internal error.
#include <string>

namespace tkgslam::io {

/// Creates `path` and its parents if missing; throws InputError when that fails.
void createOutputFolder(const std::string& path);

/// Checks, before a long run, that the file `path` will be writable at its end: its folder exists
/// and a file of that name can be opened for writing (an existing one is opened to append, its
/// contents untouched; a missing one is created and removed again). Throws InputError naming
/// `what` (e.g. "--save-map") and the reason otherwise.
void checkWritableFile(const std::string& path, const std::string& what);

}  // namespace tkgslam::io
