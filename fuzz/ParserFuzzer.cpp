// libFuzzer target, built once per harness in ParserHarnesses.h (TKGSLAM_FUZZ_HARNESS names it;
// see fuzz/CMakeLists.txt). Run through scripts/fuzz.sh.
#include "ParserHarnesses.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  tkgslam::fuzz::TKGSLAM_FUZZ_HARNESS(data, size);
  return 0;
}
