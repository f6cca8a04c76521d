// Lookahead holds frames back until their boxes are final; SlamSystem then releases them at an
// even pace, one per call and a fixed delay behind the input, not in bursts per detection.
#include <gtest/gtest.h>

#include "TestSupport.h"
#include "tkgslam/io/ConfigFile.h"
#include "tkgslam/io/TumDataset.h"
#include "tkgslam/system/SlamSystem.h"

namespace tkgslam {
namespace {

TEST(LookaheadPacing, OneFrameOutPerFrameInAtAFixedDelay) {
  TKGSLAM_REQUIRE_SHARED();
  SlamConfig config = io::loadConfig((test::sourceDir() / "configs/tum_fr1.yaml").string());
  config.deterministic = true;
  config.dynamic.mode = DynamicMode::TKG;
  config.dynamic.lookahead = true;
  config.dynamic.detect_every = 2;
  config.dynamic.detector_tiles = 4;
  config.dynamic.detector_latency = 8;
  const int delay = config.dynamic.lookaheadDelay();
  ASSERT_EQ(delay, 15);  // 2 x 4 + 8 - 1
  io::TumDatasetOptions options;
  options.depth_factor = config.depth.factor;
  io::TumDataset dataset(test::fr1xyz().string(), options);
  SlamSystem slam(config);
  const int n = 40;
  long expected = 0;
  for (int i = 0; i < n; ++i) {
    const auto out = slam.processFrame(dataset.load(i));
    // Nothing before the delay has passed, then exactly the frame `delay` behind this one.
    ASSERT_EQ(out.size(), i < delay ? 0u : 1u) << "frame " << i;
    if (!out.empty()) {
      EXPECT_EQ(out[0].index, expected++);
      EXPECT_DOUBLE_EQ(out[0].timestamp, dataset.timestamp(int(out[0].index)));
    }
  }
  // The frames still held come out at the end, in order.
  const auto rest = slam.finish();
  ASSERT_EQ(long(rest.size()), n - expected);
  for (const auto& f : rest) EXPECT_EQ(f.index, expected++);
  EXPECT_EQ(slam.trajectory().size(), size_t(n));
}

}  // namespace
}  // namespace tkgslam
