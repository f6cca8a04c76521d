#include "tkgslam/system/SlamConfig.h"

#include <algorithm>
#include <cctype>

#include <fmt/format.h>

#include "tkgslam/common/Error.h"

namespace tkgslam {

const char* toString(DynamicMode mode) {
  switch (mode) {
    case DynamicMode::Orb: return "orb";
    case DynamicMode::T: return "T";
    case DynamicMode::TK: return "TK";
    case DynamicMode::TG: return "TG";
    case DynamicMode::TKG: return "TKG";
  }
  return "?";
}

DynamicMode parseDynamicMode(const std::string& text) {
  std::string t = text;
  std::transform(t.begin(), t.end(), t.begin(), [](unsigned char c) { return char(std::toupper(c)); });
  if (t == "ORB") return DynamicMode::Orb;
  if (t == "T") return DynamicMode::T;
  if (t == "TK") return DynamicMode::TK;
  if (t == "TG") return DynamicMode::TG;
  if (t == "TKG") return DynamicMode::TKG;
  throw InputError(fmt::format("unknown dynamic mode '{}' (expected orb, T, TK, TG or TKG)", text));
}

}  // namespace tkgslam
