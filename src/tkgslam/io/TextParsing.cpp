#include "tkgslam/io/TextParsing.h"

#include <cerrno>
#include <cmath>
#include <cstdlib>

#include <fmt/format.h>

#include "tkgslam/common/Error.h"

namespace tkgslam::io {

std::vector<std::string> splitFields(const std::string& line) {
  std::vector<std::string> fields;
  std::string current;
  for (char c : line) {
    if (c == ' ' || c == '\t' || c == ',' || c == '\r') {
      if (!current.empty()) fields.push_back(std::move(current));
      current.clear();
    } else {
      current.push_back(c);
    }
  }
  if (!current.empty()) fields.push_back(std::move(current));
  return fields;
}

bool parseDouble(const std::string& token, double& value) {
  if (token.empty()) return false;
  errno = 0;
  char* end = nullptr;
  value = std::strtod(token.c_str(), &end);
  if (end != token.c_str() + token.size() || errno == ERANGE) return false;
  return std::isfinite(value);
}

bool isCommentOrBlank(const std::string& line) {
  for (char c : line) {
    if (c == '#') return true;
    if (c != ' ' && c != '\t' && c != '\r') return false;
  }
  return true;
}

void skipByteOrderMark(std::istream& in) {
  static constexpr char kBom[] = "\xEF\xBB\xBF";
  for (int i = 0; i < 3; ++i) {
    if (in.peek() != static_cast<unsigned char>(kBom[i])) {
      // A partial match is put back: the bytes belong to the first line.
      for (; i > 0; --i) in.unget();
      return;
    }
    in.get();
  }
}

std::vector<DataLine> readDataLines(std::istream& in, const std::string& source, size_t min_fields,
                                    const std::string& layout) {
  skipByteOrderMark(in);
  std::vector<DataLine> out;
  std::string line;
  int number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (isCommentOrBlank(line)) continue;
    auto fields = splitFields(line);
    if (fields.size() < min_fields) {
      throw InputError(fmt::format("{}:{}: expected '{}', got '{}'", source, number, layout, line));
    }
    out.push_back({number, std::move(line), std::move(fields)});
  }
  return out;
}

}  // namespace tkgslam::io
