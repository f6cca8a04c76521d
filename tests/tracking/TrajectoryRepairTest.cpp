// The trajectory repairs on synthetic records: camera centres on a line, some of them off it.
#include <gtest/gtest.h>

#include <memory>
#include <vector>

#include "tkgslam/data/FrameFeatures.h"
#include "tkgslam/data/KeyFrame.h"
#include "tkgslam/tracking/TrajectoryRepair.h"

namespace tkgslam {
namespace {

using tracking::FrameRecord;

constexpr double kFps = 30;

/// World -> camera pose of an unrotated camera whose centre is `centre` (world, metres).
Pose cameraAt(const Vec3& centre) {
  Pose T_cw = Pose::Identity();
  T_cw.translation() = -centre;
  return T_cw;
}

/// A keyframe at the world origin: records referenced to it have T_cr = T_cw.
std::shared_ptr<data::KeyFrame> keyFrameAtOrigin(long id = 0) {
  return std::make_shared<data::KeyFrame>(id, id, 0.0, std::make_shared<data::FrameFeatures>(), Pose::Identity());
}

/// A record at frame `k` (timestamp k / kFps) whose camera centre is `centre` (world, metres).
FrameRecord recordAt(double k, const Vec3& centre, const std::shared_ptr<data::KeyFrame>& kf,
                     bool provisional = false) {
  FrameRecord r(k / kFps, kf, Pose::Identity(), provisional);
  r.setT_cw(cameraAt(centre));
  return r;
}

Vec3 centreOf(const FrameRecord& r) { return r.T_cw().inverse().translation(); }

TEST(TrajectoryRepairTest, BridgedRecordsAreInterpolatedAndLostFramesGetRecords) {
  const auto kf = keyFrameAtOrigin();
  std::vector<FrameRecord> records{recordAt(0, Vec3(0, 0, 0), kf), recordAt(1, Vec3(1, 1, 1), kf, true),
                                   recordAt(3, Vec3(0.3, 0, 0.03), kf)};
  records[1].predicted = true;
  // Tracking resumed at records[2]: the frame before the bridged one must be the last tracked.
  auto wrong_last = records;
  EXPECT_FALSE(tracking::interpolateRecordsBefore(wrong_last, 2, 1.0 / kFps, {2.0 / kFps}));
  EXPECT_EQ(wrong_last.size(), 3u);
  EXPECT_TRUE(wrong_last[1].provisional);

  ASSERT_TRUE(tracking::interpolateRecordsBefore(records, 2, 0.0, {2.0 / kFps}));
  ASSERT_EQ(records.size(), 4u);  // the lost frame got a record
  EXPECT_DOUBLE_EQ(records[2].timestamp, 2.0 / kFps);
  for (size_t k = 1; k <= 2; ++k) {
    EXPECT_TRUE(centreOf(records[k]).isApprox(Vec3(0.1 * double(k), 0, 0.01 * double(k)), 1e-9)) << k;
    EXPECT_TRUE(records[k].interpolated);
    EXPECT_FALSE(records[k].provisional);
    EXPECT_FALSE(records[k].predicted);
  }
  EXPECT_FALSE(records[0].interpolated);
  EXPECT_FALSE(records[3].interpolated);
  // Nothing bridged or lost before records[3] now.
  EXPECT_FALSE(tracking::interpolateRecordsBefore(records, 3, 2.0 / kFps, {}));
}

TEST(TrajectoryRepairTest, InterpolatedRecordsFollowTheirNeighboursWhenInterpolatedAgain) {
  const auto kf_a = keyFrameAtOrigin(0), kf_b = keyFrameAtOrigin(1);
  std::vector<FrameRecord> records{recordAt(0, Vec3(0, 0, 0), kf_a), recordAt(1, Vec3(0.1, 0, 0), kf_a),
                                   recordAt(2, Vec3(0.2, 0, 0), kf_b)};
  records[1].interpolated = true;
  EXPECT_EQ(tracking::interpolateAgain(records), 1);
  EXPECT_TRUE(centreOf(records[1]).isApprox(Vec3(0.1, 0, 0), 1e-9));
  // A correction (loop closure) moves the later keyframe by 10 cm: the record referenced to it
  // follows, and the interpolated one between is moved half as far.
  kf_b->setPose(cameraAt(Vec3(0.1, 0, 0)));
  EXPECT_TRUE(centreOf(records[2]).isApprox(Vec3(0.3, 0, 0), 1e-9));
  EXPECT_TRUE(centreOf(records[1]).isApprox(Vec3(0.1, 0, 0), 1e-9));
  EXPECT_EQ(tracking::interpolateAgain(records), 1);
  EXPECT_TRUE(centreOf(records[1]).isApprox(Vec3(0.15, 0, 0), 1e-9));
  EXPECT_TRUE(centreOf(records[0]).isApprox(Vec3::Zero(), 1e-9));
}

TEST(TrajectoryRepairTest, FramesBridgedAtTheEndMoveOnByTheMedianStep) {
  const auto kf = keyFrameAtOrigin();
  std::vector<FrameRecord> records;
  for (int k = 0; k < 5; ++k) records.push_back(recordAt(k, Vec3(0.01 * k, 0, 0), kf));
  records.push_back(recordAt(5, Vec3(0.11, 0, 0), kf));  // one 7 cm step just before the cover
  for (int k = 6; k < 8; ++k) {
    records.push_back(recordAt(k, Vec3(0.11 + 0.07 * (k - 5), 0, 0), kf, true));  // the motion model's
    records.back().predicted = true;
  }
  records.push_back(recordAt(8, Vec3(0.5, 0.5, 0), kf, true));  // tracked on a blurred image
  EXPECT_EQ(tracking::extrapolateEnd(records, kFps, 5), 2);
  EXPECT_TRUE(centreOf(records[6]).isApprox(Vec3(0.12, 0, 0), 1e-9)) << centreOf(records[6]).transpose();
  EXPECT_TRUE(centreOf(records[7]).isApprox(Vec3(0.13, 0, 0), 1e-9)) << centreOf(records[7]).transpose();
  EXPECT_TRUE(centreOf(records[8]).isApprox(Vec3(0.5, 0.5, 0), 1e-9));  // keeps its own pose
  EXPECT_TRUE(centreOf(records[5]).isApprox(Vec3(0.11, 0, 0), 1e-9));
  // A run that ends on a tracked frame has nothing to extrapolate.
  records.resize(6);
  EXPECT_EQ(tracking::extrapolateEnd(records, kFps, 5), 0);
}

TEST(TrajectoryRepairTest, ExcursionsOffTheLineAreInterpolatedSmallOnesStay) {
  const auto kf = keyFrameAtOrigin();
  std::vector<FrameRecord> records;
  for (int k = 0; k < 20; ++k) {
    Vec3 c(0.01 * k, 0, 0);
    if (k == 5) c.y() = 0.05;                // one frame 5 cm off
    if (k == 9) c.y() = 0.02;                // 2 cm: below the 3 cm threshold
    if (k == 14 || k == 15) c.z() = 0.08;    // two frames 8 cm off
    records.push_back(recordAt(k, c, kf));
  }
  EXPECT_EQ(tracking::interpolateExcursions(records, 0.03, kFps, 3), 3);
  for (int k : {5, 14, 15}) {
    EXPECT_TRUE(centreOf(records[size_t(k)]).isApprox(Vec3(0.01 * k, 0, 0), 1e-9)) << k;
    EXPECT_TRUE(records[size_t(k)].interpolated) << k;
  }
  EXPECT_TRUE(centreOf(records[9]).isApprox(Vec3(0.09, 0.02, 0), 1e-9));
  EXPECT_FALSE(records[9].interpolated);
  EXPECT_FALSE(records[4].interpolated);
}

TEST(TrajectoryRepairTest, NoExcursionIsInterpolatedAcrossAGapInTheInput) {
  const auto kf = keyFrameAtOrigin();
  for (const double t_b : {2.0, 20.0}) {
    std::vector<FrameRecord> records{recordAt(0, Vec3(0, 0, 0), kf), recordAt(1, Vec3(0.01, 0.1, 0), kf),
                                     recordAt(t_b, Vec3(0.01 * t_b, 0, 0), kf)};
    const bool next_frame = t_b == 2.0;  // else 19 frames are missing from the input after records[1]
    EXPECT_EQ(tracking::interpolateExcursions(records, 0.03, kFps, 3), next_frame ? 1 : 0) << t_b;
    EXPECT_NEAR(centreOf(records[1]).y(), next_frame ? 0.0 : 0.1, 1e-9) << t_b;
  }
}

}  // namespace
}  // namespace tkgslam
