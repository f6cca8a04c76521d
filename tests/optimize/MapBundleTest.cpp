#include <random>

#include <gtest/gtest.h>

#include "SyntheticKeypoints.h"
#include "tkgslam/data/Map.h"
#include "tkgslam/optimize/MapBundle.h"

namespace tkgslam {
namespace {

constexpr double kDeg = M_PI / 180.0;

// Four keyframes 10 cm apart looking at 80 points 1-3 m away, every point seen by every keyframe
// at its exact (ideal) pixel with depth, all at pyramid level 0.
class SmallMap : public ::testing::Test {
 protected:
  void SetUp() override {
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> ux(-0.8, 0.8), uz(1.0, 3.0);
    for (int c = 0; c < 4; ++c) {
      Pose T = Pose::Identity();
      T.linear() = Eigen::AngleAxisd(0.03 * c, Vec3(0, 1, 0)).toRotationMatrix();
      T.translation() = Vec3(-0.1 * c, 0.02 * c, 0);
      truth_.push_back(T);
    }
    for (int p = 0; p < 80; ++p) points_.push_back(Vec3(ux(rng), 0.7 * ux(rng), uz(rng)));
    for (int c = 0; c < 4; ++c) {
      auto F = std::make_shared<data::FrameFeatures>();
      for (const Vec3& pw : points_) test::addProjectedKeypoint(*F, truth_[size_t(c)] * pw, K_);
      F->descriptors = cv::Mat::zeros(F->size(), 32, CV_8U);
      auto kf = std::make_shared<data::KeyFrame>(map_.newKeyFrameId(), c, c, F, truth_[size_t(c)]);
      kf->map_points.resize(points_.size());
      map_.addKeyFrame(kf);
      kfs_.push_back(kf);
    }
    for (size_t p = 0; p < points_.size(); ++p) {
      auto mp = std::make_shared<data::MapPoint>(map_.newMapPointId(), points_[p], kfs_[0].get(), cv::Mat::zeros(1, 32, CV_8U));
      for (auto& kf : kfs_) {
        mp->observations[kf.get()] = int(p);
        kf->addMapPoint(mp, int(p));
      }
      map_.addMapPoint(mp);
    }
  }

  std::vector<data::KeyFrame*> window(std::initializer_list<int> ids) const {
    std::vector<data::KeyFrame*> w;
    for (int i : ids) w.push_back(kfs_[size_t(i)].get());
    return w;
  }

  optimize::PinholeIntrinsics K_{517.3, 516.5, 318.6, 255.3, 40.0};
  feature::ScalePyramid pyr_ = feature::ScalePyramid::make(8, 1.2);
  data::Map map_;
  std::vector<Pose> truth_;
  std::vector<Vec3> points_;
  std::vector<std::shared_ptr<data::KeyFrame>> kfs_;
};

TEST_F(SmallMap, WindowKeyFramesAreFreeTheirPointsObserversFixed) {
  optimize::MapBundle b(map_, window({2, 3}), pyr_);
  const auto& pb = b.problem();
  ASSERT_EQ(pb.poses.size(), 4u);  // the window, then keyframes 0 and 1 as observers
  EXPECT_EQ(b.keyFrames()[0], kfs_[2]);
  EXPECT_EQ(b.keyFrames()[1], kfs_[3]);
  EXPECT_EQ(pb.fixed_pose, (std::vector<char>{0, 0, 1, 1}));
  EXPECT_EQ(pb.points.size(), points_.size());  // each point once, though both window keyframes see it
  EXPECT_EQ(pb.observations.size(), 4 * points_.size());
  EXPECT_TRUE(b.contains(*kfs_[0]->map_points[5]));

  optimize::MapBundle all(map_, window({0, 1, 2, 3}), pyr_);
  EXPECT_EQ(all.problem().fixed_pose, (std::vector<char>{1, 0, 0, 0}));  // keyframe 0 holds the gauge
  all.fix(kfs_[1].get());
  EXPECT_EQ(all.problem().fixed_pose, (std::vector<char>{1, 1, 0, 0}));
}

TEST_F(SmallMap, ApplyWritesBackPosesAndPointsAndDropsOutliers) {
  // Keyframe 2 and the points start off; one observation of keyframe 3 is 60 px wrong.
  Pose off = truth_[2];
  off.linear() = Eigen::AngleAxisd(1 * kDeg, Vec3(1, 0, 0)).toRotationMatrix() * off.linear();
  off.translation() += Vec3(0.03, -0.02, 0.01);
  kfs_[2]->setPose(off);
  for (const auto& mp : map_.mapPoints()) mp->pos_w += Vec3(0.01, 0.0, -0.01);
  auto F3 = std::const_pointer_cast<data::FrameFeatures>(kfs_[3]->features);
  F3->ideal[7].pt.x += 60;
  F3->u_right[7] += 60;

  optimize::MapBundle b(map_, window({1, 2, 3}), pyr_);
  const auto outlier = optimize::solveBundle(b.problem(), K_, {});
  ASSERT_EQ(std::count(outlier.begin(), outlier.end(), 1), 1);
  b.apply(map_, outlier, pyr_);

  EXPECT_TRUE(kfs_[0]->T_cw().isApprox(truth_[0]));  // fixed
  for (int c = 1; c < 4; ++c) {
    EXPECT_LT((kfs_[size_t(c)]->centre() - truth_[size_t(c)].inverse().translation()).norm(), 1e-3) << c;
  }
  for (size_t p = 0; p < points_.size(); ++p) EXPECT_LT((kfs_[0]->map_points[p]->pos_w - points_[p]).norm(), 1e-3) << p;
  EXPECT_EQ(kfs_[3]->map_points[7], nullptr);  // the outlier observation was removed from the map
  EXPECT_EQ(kfs_[0]->map_points[7]->observations.count(kfs_[3].get()), 0u);
}

}  // namespace
}  // namespace tkgslam
