// Replays the fuzzers' seed corpora and every input they ever crashed on (fuzz/regressions/)
// through the same harnesses, so a fixed parser bug stays fixed in the normal (gcc) test suite.
#include <gtest/gtest.h>

#include "ParserHarnesses.h"
#include "TestSupport.h"

namespace tkgslam {
namespace {

using Harness = void (*)(const std::uint8_t*, std::size_t);

// Runs `harness` on every file of fuzz/{corpus,regressions}/<name>; returns how many it ran.
int replay(const std::string& name, Harness harness) {
  int count = 0;
  for (const char* kind : {"corpus", "regressions"}) {
    const auto dir = test::sourceDir() / "fuzz" / kind / name;
    if (!std::filesystem::is_directory(dir)) continue;
    for (const auto& file : std::filesystem::directory_iterator(dir)) {
      const std::string bytes = test::readFile(file.path());
      SCOPED_TRACE(file.path().string());
      EXPECT_NO_THROW(harness(reinterpret_cast<const std::uint8_t*>(bytes.data()), bytes.size()));
      ++count;
    }
  }
  return count;
}

TEST(FuzzRegression, TumListsInputs) { EXPECT_GE(replay("tum_lists", fuzz::fuzzTumLists), 2); }
TEST(FuzzRegression, TrajectoryInputs) { EXPECT_GE(replay("trajectory", fuzz::fuzzTrajectory), 3); }
TEST(FuzzRegression, ConfigInputs) { EXPECT_GE(replay("config", fuzz::fuzzConfig), 4); }
TEST(FuzzRegression, MapFileInputs) { EXPECT_GE(replay("map_file", fuzz::fuzzMapFile), 1); }
TEST(FuzzRegression, OnnxGraphInputs) { EXPECT_GE(replay("onnx_graph", fuzz::fuzzOnnxGraph), 2); }

}  // namespace
}  // namespace tkgslam
