#pragma once
// Number checks for CLI options whose failure message a user can read: CLI11 2.1's
// PositiveNumber / NonNegativeNumber report "not in range 0.000000 to" DBL_MAX written out in full.
#include <cmath>
#include <string>

#include <CLI/CLI.hpp>

namespace tkgslam::app {

namespace detail {
enum class Sign { Positive, NonNegative, Any };

inline CLI::Validator numberCheck(const char* name, Sign sign) {
  return CLI::Validator(
      [sign](std::string& value) -> std::string {
        double v = 0;
        if (!CLI::detail::lexical_cast(value, v) || std::isnan(v)) return "'" + value + "' is not a number";
        if (!std::isfinite(v)) return "must be finite, got " + value;
        if (sign == Sign::Any || v > 0 || (sign == Sign::NonNegative && v == 0)) return {};
        return std::string("must be ") + (sign == Sign::NonNegative ? "0 or more" : "more than 0") + ", got " + value;
      },
      name);
}
}  // namespace detail

/// Accepts finite numbers > 0.
inline CLI::Validator positiveNumber() { return detail::numberCheck("POSITIVE", detail::Sign::Positive); }
/// Accepts finite numbers >= 0.
inline CLI::Validator nonNegativeNumber() { return detail::numberCheck("NONNEGATIVE", detail::Sign::NonNegative); }
/// Accepts any finite number.
inline CLI::Validator finiteNumber() { return detail::numberCheck("FINITE", detail::Sign::Any); }

}  // namespace tkgslam::app
