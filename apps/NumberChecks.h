#pragma once
// Number checks for CLI options whose failure message a user can read: CLI11 2.1's
// PositiveNumber / NonNegativeNumber report "not in range 0.000000 to" DBL_MAX written out in full.
#include <string>

#include <CLI/CLI.hpp>

namespace tkgslam::app {

namespace detail {
inline CLI::Validator numberCheck(const char* name, bool allow_zero) {
  return CLI::Validator(
      [allow_zero](std::string& value) -> std::string {
        double v = 0;
        if (!CLI::detail::lexical_cast(value, v)) return "'" + value + "' is not a number";
        if (v > 0 || (allow_zero && v == 0)) return {};
        return std::string("must be ") + (allow_zero ? "0 or more" : "more than 0") + ", got " + value;
      },
      name);
}
}  // namespace detail

/// Accepts numbers > 0.
inline CLI::Validator positiveNumber() { return detail::numberCheck("POSITIVE", false); }
/// Accepts numbers >= 0.
inline CLI::Validator nonNegativeNumber() { return detail::numberCheck("NONNEGATIVE", true); }

}  // namespace tkgslam::app
