#include <random>

#include <gtest/gtest.h>

#include "SyntheticKeypoints.h"
#include "tkgslam/camera/PinholeCamera.h"
#include "tkgslam/data/Map.h"
#include "tkgslam/mapping/LocalMapper.h"

namespace tkgslam {
namespace {

// Four keyframes 5 cm apart seeing 120 points 1-3 m away at their exact pixels (with depth). The
// newest keyframe also sees 150 points on a "person" who moved 8 cm between its image and the
// others': those pixels fit the newest keyframe only if it were 8 cm further along - as people's
// points the masks missed pull a new keyframe in a local BA.
class PersonInTheWindow : public ::testing::Test {
 protected:
  void SetUp() override {
    config_.camera.fx = 517.3;
    config_.camera.fy = 516.5;
    config_.camera.cx = 318.6;
    config_.camera.cy = 255.3;
    config_.depth.baseline_fx = 40.0;
    config_.deterministic = true;
    camera_ = std::make_unique<camera::PinholeCamera>(config_.camera);
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> ux(-0.8, 0.8), uz(1.0, 3.0);
    for (int c = 0; c < 4; ++c) {
      Pose T = Pose::Identity();
      T.translation() = Vec3(-0.05 * c, 0, 0);
      truth_.push_back(T);
    }
    const auto K = optimize::intrinsicsOf(camera_->fx(), camera_->fy(), camera_->cx(), camera_->cy(), config_.depth.baseline_fx);
    const Vec3 person_step(0.08, 0, 0);  // where the person's points appear to the newest keyframe
    std::vector<Vec3> points;
    std::vector<char> person;
    for (int p = 0; p < 270; ++p) {
      points.push_back(Vec3(ux(rng), 0.7 * ux(rng), uz(rng)));
      person.push_back(p >= 120);
    }
    for (int c = 0; c < 4; ++c) {
      auto F = std::make_shared<data::FrameFeatures>();
      for (size_t p = 0; p < points.size(); ++p) {
        const Vec3 pw = person[p] && c == 3 ? Vec3(points[p] + person_step) : points[p];
        test::addProjectedKeypoint(*F, truth_[size_t(c)] * pw, K);
      }
      F->descriptors = cv::Mat::zeros(F->size(), 32, CV_8U);
      auto kf = std::make_shared<data::KeyFrame>(map_.newKeyFrameId(), c, c, F, truth_[size_t(c)]);
      kf->map_points.resize(points.size());
      map_.addKeyFrame(kf);
      kfs_.push_back(kf);
    }
    for (size_t p = 0; p < points.size(); ++p) {
      auto mp = std::make_shared<data::MapPoint>(map_.newMapPointId(), points[p], kfs_[0].get(), cv::Mat::zeros(1, 32, CV_8U));
      for (auto& kf : kfs_) {
        if (person[p] && kf->id != 3 && kf->id != 2) continue;  // person points: seen by the last two
        mp->observations[kf.get()] = int(p);
        kf->addMapPoint(mp, int(p));
      }
      map_.addMapPoint(mp);
    }
    for (auto& kf : kfs_) kf->updateConnections();
  }

  double newestShift() const { return (kfs_[3]->centre() - truth_[3].inverse().translation()).norm(); }

  SlamConfig config_;
  std::unique_ptr<camera::PinholeCamera> camera_;
  feature::ScalePyramid pyr_ = feature::ScalePyramid::make(8, 1.2);
  data::Map map_;
  std::vector<Pose> truth_;
  std::vector<std::shared_ptr<data::KeyFrame>> kfs_;
};

TEST_F(PersonInTheWindow, WithoutTheHoldTheBundleDragsTheNewKeyFrame) {
  ASSERT_EQ(config_.mapping.max_keyframe_shift_m, 0);  // off by default
  ASSERT_EQ(config_.mapping.max_keyframe_shift_deg, 0);
  mapping::LocalMapper mapper(map_, *camera_, pyr_, config_);
  mapper.localBundleAdjustment(*kfs_[3]);
  std::printf("without the hold: new keyframe moved %.4f m\n", newestShift());
  EXPECT_GT(newestShift(), 0.06);
  EXPECT_EQ(mapper.stats().keyframes_held, 0);
}

TEST_F(PersonInTheWindow, TheNewKeyFrameIsHeldWhereTrackingPutItAndThePersonsPointsDropOut) {
  config_.mapping.max_keyframe_shift_m = 0.03;
  config_.mapping.max_keyframe_shift_deg = 1.5;
  mapping::LocalMapper mapper(map_, *camera_, pyr_, config_);
  mapper.localBundleAdjustment(*kfs_[3]);
  EXPECT_EQ(mapper.stats().keyframes_held, 1);
  EXPECT_LT(newestShift(), 1e-9);
  for (int c = 1; c < 3; ++c) {  // the others stay on the truth
    EXPECT_LT((kfs_[size_t(c)]->centre() - truth_[size_t(c)].inverse().translation()).norm(), 0.005) << c;
  }
  // The person's observations in the new keyframe were the outliers: removed from the map.
  int person_seen = 0;
  for (size_t p = 120; p < kfs_[3]->map_points.size(); ++p) person_seen += kfs_[3]->map_points[p] != nullptr;
  EXPECT_LT(person_seen, 15);
}

}  // namespace
}  // namespace tkgslam
