#pragma once
// Opening a file the user named. On Linux an ifstream opens a folder without complaint and then
// reads nothing, which surfaced as "has no poses" or "expected a YAML mapping"; every input file is
// opened here instead, so each failure says what is wrong with the path.
#include <fstream>
#include <string>

namespace tkgslam::io {

/// Opens `path` for reading. Throws InputError "<what> '<path>' does not exist" (a relative path
/// followed by where it was looked for), "... is a folder, not a file" or "... cannot be read"
/// (`what` e.g. "config file").
std::ifstream openInputFile(const std::string& path, const std::string& what,
                            std::ios::openmode mode = std::ios::in);

}  // namespace tkgslam::io
