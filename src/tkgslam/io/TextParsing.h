#pragma once
// Small helpers shared by the line-oriented text parsers (TUM lists, trajectories).
#include <string>
#include <vector>

namespace tkgslam::io {

/// Splits a line on spaces, tabs and commas (the separators the TUM tools accept).
std::vector<std::string> splitFields(const std::string& line);

/// Parses a whole token as a finite double. Returns false on any trailing garbage, NaN or inf.
bool parseDouble(const std::string& token, double& value);

/// True for lines the TUM tools ignore: empty, whitespace only, or starting with '#'.
bool isCommentOrBlank(const std::string& line);

}  // namespace tkgslam::io
