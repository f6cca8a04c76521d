#include <gtest/gtest.h>
#include <opencv2/imgproc.hpp>

#include "tkgslam/dynamic/BoxFlow.h"

namespace tkgslam {
namespace {

/// Smooth random texture (LK needs gradients at every scale), 8-bit grey.
cv::Mat texture(int w, int h, int seed) {
  cv::Mat t(h, w, CV_8U);
  cv::RNG rng(seed);
  rng.fill(t, cv::RNG::UNIFORM, 0, 255);
  cv::GaussianBlur(t, t, cv::Size(0, 0), 2.0);
  cv::normalize(t, t, 0, 255, cv::NORM_MINMAX);
  return t;
}

cv::Mat shifted(const cv::Mat& image, float dx, float dy) {
  cv::Mat out;
  const cv::Mat m = (cv::Mat_<double>(2, 3) << 1, 0, dx, 0, 1, dy);
  cv::warpAffine(image, out, m, image.size(), cv::INTER_LINEAR, cv::BORDER_REFLECT);
  return out;
}

TEST(BoxFlow, MovesABoxByTheImageMotion) {
  const cv::Mat a = texture(640, 480, 1);
  const cv::Mat b = shifted(a, 9.5f, -4.0f);
  dynamic::BoxFlow flow;
  const auto moved = flow.propagate(flow.prepare(a), flow.prepare(b), {cv::Rect2f(200, 150, 120, 200)});
  ASSERT_TRUE(moved[0]);
  EXPECT_NEAR(moved[0]->x, 209.5f, 0.3f);
  EXPECT_NEAR(moved[0]->y, 146.0f, 0.3f);
  EXPECT_NEAR(moved[0]->width, 120.0f, 1.0f);
  EXPECT_NEAR(moved[0]->height, 200.0f, 1.0f);
}

TEST(BoxFlow, WithDepthTheBoxFollowsTheNearObjectNotTheBackground) {
  // A person-like patch (1 m away) walks right and down while the background (2.5 m) drifts
  // left with the camera; the patch fills only ~40 % of its box, so without depth the
  // background outvotes it.
  const cv::Mat background = texture(640, 480, 2), person = texture(80, 200, 3);
  const cv::Rect at0(250, 120, 80, 200), at1(262, 125, 80, 200);
  cv::Mat f0 = background.clone(), f1 = shifted(background, -3.0f, 0.0f);
  person.copyTo(f0(at0));
  person.copyTo(f1(at1));
  cv::Mat depth0(480, 640, CV_32F, cv::Scalar(2.5f));
  depth0(at0).setTo(1.0f);
  const cv::Rect2f box(210, 100, 160, 240);  // the patch plus background around it

  dynamic::BoxFlow with_depth;
  const auto d = with_depth.propagate(with_depth.prepare(f0, depth0), with_depth.prepare(f1), {box});
  ASSERT_TRUE(d[0]);
  EXPECT_NEAR(d[0]->x - box.x, 12.0f, 1.0f);
  EXPECT_NEAR(d[0]->y - box.y, 5.0f, 1.0f);

  const auto n = with_depth.propagate(with_depth.prepare(f0), with_depth.prepare(f1), {box});
  ASSERT_TRUE(n[0]);
  EXPECT_LT(n[0]->x - box.x, 4.0f) << "without depth the background outvotes the person";
}

TEST(BoxFlow, ABoxCutByTheImageBorderKeepsThatEdgeOnTheBorder) {
  // Content moves 10 px right: a box touching the left border grows to the right (more of the
  // person comes into view) instead of leaving a strip of the person outside it.
  const cv::Mat a = texture(640, 480, 4);
  const cv::Mat b = shifted(a, 10.0f, 0.0f);
  dynamic::BoxFlow flow;
  const auto moved = flow.propagate(flow.prepare(a), flow.prepare(b), {cv::Rect2f(0, 100, 100, 200)});
  ASSERT_TRUE(moved[0]);
  EXPECT_FLOAT_EQ(moved[0]->x, 0.0f);
  EXPECT_NEAR(moved[0]->br().x, 110.0f, 0.5f);
}

TEST(BoxFlow, NoMeasurementWithoutTexture) {
  const cv::Mat flat(480, 640, CV_8U, cv::Scalar(128));
  dynamic::BoxFlow flow;
  const auto moved = flow.propagate(flow.prepare(flat), flow.prepare(flat), {cv::Rect2f(100, 100, 80, 80)});
  EXPECT_FALSE(moved[0]);
}

}  // namespace
}  // namespace tkgslam
