#include <random>
#include <set>

#include <gtest/gtest.h>

#include "tkgslam/dynamic/BoxKalmanFilter.h"
#include "tkgslam/dynamic/BoxTracker.h"
#include "tkgslam/dynamic/Hungarian.h"

namespace tkgslam {
namespace {

using dynamic::Detection;

TEST(BoxKalmanFilter, PredictAndUpdateMatchHandComputation) {
  // Box centred at (100, 50), 40 x 20: z = [100, 50, 800, 2].
  dynamic::KalmanParams kp;  // q 0.01, r 0.1, P0 = diag(10 x4, 1000 x3)
  dynamic::BoxKalmanFilter kf(cv::Rect2f(80, 40, 40, 20), kp);
  EXPECT_DOUBLE_EQ(kf.state()[0], 100.0);
  EXPECT_DOUBLE_EQ(kf.state()[2], 800.0);
  EXPECT_DOUBLE_EQ(kf.state()[3], 2.0);
  kf.predict();
  // Zero velocity: the state is unchanged; P_xx = 10 + 1000 + 0.01, P_x,vx = 1000, P_rr = 10.01.
  EXPECT_DOUBLE_EQ(kf.state()[0], 100.0);
  EXPECT_NEAR(kf.covariance()(0, 0), 1010.01, 1e-9);
  EXPECT_NEAR(kf.covariance()(0, 4), 1000.0, 1e-9);
  EXPECT_NEAR(kf.covariance()(3, 3), 10.01, 1e-9);
  // Measure the centre 10 px to the right: gain on x = 1010.01 / (1010.01 + 0.1),
  // gain on vx = 1000 / (1010.01 + 0.1).
  kf.update(cv::Rect2f(90, 40, 40, 20));
  const double S = 1010.01 + 0.1;
  EXPECT_NEAR(kf.state()[0], 100.0 + 10.0 * 1010.01 / S, 1e-9);
  EXPECT_NEAR(kf.state()[4], 10.0 * 1000.0 / S, 1e-9);
  EXPECT_NEAR(kf.covariance()(0, 0), 1010.01 - 1010.01 * 1010.01 / S, 1e-9);
  // The next prediction moves on with the estimated velocity.
  const cv::Rect2f p = kf.predict();
  EXPECT_NEAR(p.x + p.width / 2, kf.state()[0], 1e-4);
  EXPECT_GT(p.x + p.width / 2, 118.0);
}

double bruteForce(const std::vector<std::vector<double>>& c) {
  const int n = int(c.size()), m = int(c[0].size());
  std::vector<int> cols(m);
  for (int j = 0; j < m; ++j) cols[j] = j;
  double best = 1e300;
  do {  // each permutation assigns the first min(n, m) columns/rows
    double s = 0;
    if (n <= m) {
      for (int i = 0; i < n; ++i) s += c[i][cols[i]];
    } else {
      continue;
    }
    best = std::min(best, s);
  } while (std::next_permutation(cols.begin(), cols.end()));
  return best;
}

TEST(Hungarian, MatchesBruteForceOnRandomMatrices) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(0, 1);
  for (int trial = 0; trial < 200; ++trial) {
    const int n = 1 + int(rng() % 5), m = n + int(rng() % 3);
    std::vector<std::vector<double>> c(n, std::vector<double>(m));
    for (auto& row : c) {
      for (auto& x : row) x = (trial % 3 == 0) ? double(rng() % 4) : u(rng);  // ties too
    }
    const auto a = dynamic::solveAssignment(c);
    double s = 0;
    std::vector<char> used(m, 0);
    for (int i = 0; i < n; ++i) {
      ASSERT_GE(a[i], 0);
      ASSERT_FALSE(used[a[i]]) << "column used twice";
      used[a[i]] = 1;
      s += c[i][a[i]];
    }
    EXPECT_NEAR(s, bruteForce(c), 1e-9) << "trial " << trial;
    // More rows than columns: the transposed problem leaves rows unassigned.
    std::vector<std::vector<double>> t(m, std::vector<double>(n));
    for (int i = 0; i < n; ++i) {
      for (int j = 0; j < m; ++j) t[j][i] = c[i][j];
    }
    const auto b = dynamic::solveAssignment(t);
    double st = 0;
    int assigned = 0;
    for (int j = 0; j < m; ++j) {
      if (b[j] >= 0) st += t[j][b[j]], ++assigned;
    }
    EXPECT_EQ(assigned, n);
    EXPECT_NEAR(st, s, 1e-9);
  }
}

Detection box(float x, float y, float w = 60, float h = 120) {
  Detection d;
  d.box = cv::Rect2f(x, y, w, h);
  d.score = 0.8f;
  return d;
}

TEST(BoxTracker, FillsAMissedDetectionForOneToTwoFramesThenLetsTheTrackDie) {
  dynamic::BoxTrackerParams p;
  p.max_age = 3;
  dynamic::BoxTracker tracker(p);
  // Two people walking right at 5 px/frame.
  for (int f = 0; f < 6; ++f) {
    const auto out = tracker.update({box(100 + 5.f * f, 100), box(400 + 5.f * f, 120)});
    ASSERT_EQ(out.size(), 2u);
    for (const auto& d : out) EXPECT_FALSE(d.predicted);
  }
  // The second person is missed for two frames: it is filled in where it should be.
  for (int f = 6; f < 8; ++f) {
    const auto out = tracker.update({box(100 + 5.f * f, 100)});
    ASSERT_EQ(out.size(), 2u) << "frame " << f;
    EXPECT_TRUE(out[1].predicted);
    EXPECT_GT(dynamic::iou(out[1].box, box(400 + 5.f * f, 120).box), 0.7f) << out[1].box;
  }
  // Detected again: same track, no prediction needed.
  auto out = tracker.update({box(140, 100), box(440, 120)});
  ASSERT_EQ(out.size(), 2u);
  EXPECT_FALSE(out[1].predicted);
  const int id = out[1].track_id;
  // Gone for good: filled for max_age frames, then the track dies.
  int filled = 0;
  for (int f = 9; f < 15; ++f) {
    out = tracker.update({box(100 + 5.f * f, 100)});
    for (const auto& d : out) filled += d.predicted && d.track_id == id;
  }
  EXPECT_EQ(filled, 3);
  EXPECT_EQ(tracker.liveTracks(), 1);
}

TEST(BoxTracker, NoFillWhenTheDetectionCountDoesNotDrop) {
  dynamic::BoxTracker tracker;
  tracker.update({box(100, 100)});
  tracker.update({box(105, 100)});
  // A new person appears far away while the first is missed: counts are equal, nothing filled.
  const auto out = tracker.update({box(500, 300)});
  ASSERT_EQ(out.size(), 1u);
  EXPECT_FALSE(out[0].predicted);
}

TEST(BoxTracker, DetectionsEightFramesApartKeepTheirTrackAndGainVelocity) {
  // A person walking 10 px/frame, detected every 8th frame (80 px apart: IoU 0 with a box 60 px
  // wide): the centre gate keeps one track, whose prediction then moves with the person.
  dynamic::BoxTracker tracker;
  int id = -1;
  for (int run = 0; run < 4; ++run) {
    const auto out = tracker.update({box(100 + 80.f * run, 100)});
    ASSERT_EQ(out.size(), 1u);
    if (run == 0) id = out[0].track_id;
    EXPECT_EQ(out[0].track_id, id) << "run " << run;
    for (int f = 1; f < 8; ++f) tracker.predictAll();
  }
  EXPECT_EQ(tracker.liveTracks(), 1);
  // After the runs, the prediction 4 frames on is near where the person is.
  tracker.update({box(100 + 80.f * 4, 100)});
  std::vector<Detection> p;
  for (int f = 1; f <= 4; ++f) p = tracker.predictAll();
  ASSERT_EQ(p.size(), 1u);
  EXPECT_GT(dynamic::iou(p[0].box, box(100 + 80.f * 4 + 40, 100).box), 0.6f) << p[0].box;

  // IoU alone (the paper's gate) starts a new track on every run.
  dynamic::BoxTrackerParams iou_only;
  iou_only.centre_gate = 0;
  dynamic::BoxTracker plain(iou_only);
  std::set<int> ids;
  for (int run = 0; run < 3; ++run) {
    ids.insert(plain.update({box(100 + 80.f * run, 100)})[0].track_id);
    for (int f = 1; f < 8; ++f) plain.predictAll();
  }
  EXPECT_EQ(ids.size(), 3u);
}

TEST(BoxTracker, CentreGateRejectsFarOrDifferentlySizedBoxes) {
  dynamic::BoxTracker tracker;
  const int id = tracker.update({box(100, 100)})[0].track_id;
  tracker.predictAll();
  // One frame later a box 150 px away is another person, not this one moved.
  EXPECT_NE(tracker.update({box(250, 100)})[0].track_id, id);
  // A box of a fifth of the size at the same place is not the same object either.
  dynamic::BoxTracker second;
  const int id2 = second.update({box(100, 100)})[0].track_id;
  for (int f = 1; f < 8; ++f) second.predictAll();
  EXPECT_NE(second.update({box(140, 140, 20, 60)})[0].track_id, id2);
}

TEST(BoxTracker, MovedBoxesCorrectThePrediction) {
  // Flow (or any other measurement) says the person moved 12 px right: the predicted box follows
  // it instead of standing still (a new track has no velocity yet).
  dynamic::BoxTracker tracker;
  tracker.update({box(100, 100)});
  const auto last = tracker.lastBoxes();
  ASSERT_EQ(last.size(), 1u);
  const dynamic::BoxTracker::Moved moved{cv::Rect2f(last[0].x + 12, last[0].y, last[0].width, last[0].height)};
  const auto out = tracker.predictAll({}, &moved);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_NEAR(out[0].box.x, 112.0f, 0.1f);
  EXPECT_TRUE(out[0].predicted);
}

}  // namespace
}  // namespace tkgslam
