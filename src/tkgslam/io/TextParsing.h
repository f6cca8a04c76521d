#pragma once
// Small helpers shared by the line-oriented text parsers (TUM lists, trajectories).
#include <istream>
#include <string>
#include <vector>

namespace tkgslam::io {

/// Splits a line on spaces, tabs and commas (the separators the TUM tools accept).
std::vector<std::string> splitFields(const std::string& line);

/// Parses a whole token as a finite double. Returns false on any trailing garbage, NaN or inf.
bool parseDouble(const std::string& token, double& value);

/// True for lines the TUM tools ignore: empty, whitespace only, or starting with '#'.
bool isCommentOrBlank(const std::string& line);

/// Skips a UTF-8 byte order mark at the start of `in` (Windows editors write one; it would make
/// the first line's first field unreadable, though invisible in the error message).
void skipByteOrderMark(std::istream& in);

/// A line of a list that is not a comment or blank, split into fields.
struct DataLine {
  int number = 0;  ///< in the file, from 1
  std::string text;
  std::vector<std::string> fields;
};

/// The data lines of `in` (after a byte order mark). Throws InputError "source:N: expected '<layout>', got '<line>'" for the
/// first with fewer than `min_fields` fields.
std::vector<DataLine> readDataLines(std::istream& in, const std::string& source, size_t min_fields,
                                    const std::string& layout);

}  // namespace tkgslam::io
