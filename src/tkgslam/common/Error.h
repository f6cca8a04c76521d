#pragma once
// Error types. Every failure caused by user input (files, configs, arguments) is reported as
// InputError with a message naming the offending file/line; the CLI turns it into exit code 2.
#include <stdexcept>
#include <string>

namespace tkgslam {

/// Bad input from the user: missing/malformed file, invalid config value, bad argument.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace tkgslam
