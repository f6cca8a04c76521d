#include <sys/resource.h>

#include <cstdlib>
#include <cstring>

#include <gtest/gtest.h>

#include "tkgslam/common/MallocTuning.h"

#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
#define TKGSLAM_OWN_ALLOCATOR 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer) || __has_feature(thread_sanitizer)
#define TKGSLAM_OWN_ALLOCATOR 1
#endif
#endif

namespace tkgslam {
namespace {

[[maybe_unused]] long minorFaults() {  // unused where the test skips (sanitizer builds)
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_minflt;
}

// ctest runs each test in a process of its own, so glibc's thresholds are still the adaptive ones
// here. A frame's buffers, several of ~1 MB at once (float depth, pyramid levels): with the adaptive
// thresholds the heap is trimmed below them when they are freed (the trim threshold is twice the
// largest block freed so far), and every frame faults their ~1200 pages in again.
TEST(MallocTuning, AFramesImageBuffersAreReusedWithoutFaultingTheirPagesAgain) {
#if defined(TKGSLAM_OWN_ALLOCATOR) || !defined(__GLIBC__)
  GTEST_SKIP() << "glibc's malloc is not the allocator in this build";
#else
  common::tuneMallocForFrames();
  constexpr size_t kBytes = 640 * 480 * 4;
  const auto frame = [](int i) {
    char* p[4];
    for (auto& b : p) {
      b = static_cast<char*>(std::malloc(kBytes));
      std::memset(b, i, kBytes);
    }
    const int first = p[3][0];
    for (auto& b : p) std::free(b);
    return first;
  };
  frame(0);
  const long before = minorFaults();
  int sum = 0;
  for (int i = 1; i <= 20; ++i) sum += frame(i);
  const long faults = minorFaults() - before;
  EXPECT_EQ(sum, 210);
  EXPECT_LT(faults, 100) << "20 frames' buffers faulted " << faults << " pages in (one frame's are ~1200)";
#endif
}

}  // namespace
}  // namespace tkgslam
