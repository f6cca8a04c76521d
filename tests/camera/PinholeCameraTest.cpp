#include <gtest/gtest.h>

#include "tkgslam/camera/PinholeCamera.h"
#include "tkgslam/common/Error.h"

namespace tkgslam {
namespace {

camera::CameraParams fr1() {
  camera::CameraParams p;
  p.fx = 517.306408;
  p.fy = 516.469215;
  p.cx = 318.643040;
  p.cy = 255.313989;
  p.distortion = {0.262383, -0.953104, -0.005358, 0.002628, 1.163314};
  return p;
}

TEST(PinholeCamera, ProjectUnprojectRoundTrip) {
  camera::PinholeCamera cam(fr1());
  const Vec3 p(0.3, -0.2, 1.7);
  const Vec2 uv = cam.project(p);
  EXPECT_NEAR(uv.x(), 517.306408 * 0.3 / 1.7 + 318.643040, 1e-9);
  EXPECT_TRUE(cam.unproject(uv, 1.7).isApprox(p, 1e-12));
}

TEST(PinholeCamera, DistortThenUndistortIsIdentity) {
  camera::PinholeCamera cam(fr1());
  for (const Vec2& ideal : {Vec2(320, 240), Vec2(50, 40), Vec2(600, 450), Vec2(100, 400)}) {
    const Vec2 raw = cam.distort(ideal);
    const auto back = cam.undistort({cv::Point2f(float(raw.x()), float(raw.y()))});
    EXPECT_NEAR(back[0].x, ideal.x(), 0.05);
    EXPECT_NEAR(back[0].y, ideal.y(), 0.05);
  }
  // fr1's k1 > 0 (pincushion): a corner pixel moves inwards when undistorted.
  const auto c = cam.undistort({cv::Point2f(0, 0)});
  EXPECT_GT(c[0].x, 5.0f);
  EXPECT_GT(cam.minX(), 5.0);
  EXPECT_LT(cam.maxX(), 635.0);
}

TEST(PinholeCamera, RejectsInvalidIntrinsics) {
  auto p = fr1();
  p.fx = -1;
  EXPECT_THROW(camera::PinholeCamera{p}, InputError);
  p = fr1();
  p.cx = 900;
  EXPECT_THROW(camera::PinholeCamera{p}, InputError);
}

}  // namespace
}  // namespace tkgslam
