#include <opencv2/dnn.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <gtest/gtest.h>

#include "TestSupport.h"
#include "tkgslam/dynamic/Detection.h"
#include "tkgslam/dynamic/YoloHeadResize.h"

namespace tkgslam {
namespace {

cv::dnn::Net loadModel() {
  cv::dnn::Net net = cv::dnn::readNetFromONNX(test::yoloModel());
  net.setPreferableBackend(cv::dnn::DNN_BACKEND_OPENCV);
  net.setPreferableTarget(cv::dnn::DNN_TARGET_CPU);
  return net;
}

// The raw output (rows of cx, cy, w, h, objectness, classes) for `img` letterboxed into `input`.
cv::Mat run(cv::dnn::Net& net, const cv::Mat& img, cv::Size input, float* scale, cv::Point* offset) {
  const float r = std::min(float(input.width) / img.cols, float(input.height) / img.rows);
  const cv::Size fitted(int(std::lround(img.cols * r)), int(std::lround(img.rows * r)));
  cv::Mat canvas(input, CV_8UC3, cv::Scalar(114, 114, 114));
  *offset = cv::Point((input.width - fitted.width) / 2, (input.height - fitted.height) / 2);
  cv::resize(img, canvas(cv::Rect(*offset, fitted)), fitted);
  *scale = r;
  net.setInput(cv::dnn::blobFromImage(canvas, 1.0 / 255.0, cv::Size(), cv::Scalar(), true, false));
  return net.forward().clone();
}

// Person boxes scored above 0.5, in image pixels.
std::vector<cv::Rect2f> persons(const cv::Mat& out, float r, cv::Point offset) {
  std::vector<cv::Rect2f> boxes;
  for (int i = 0; i < out.size[1]; ++i) {
    const float* row = out.ptr<float>(0, i);
    if (row[4] * row[5] <= 0.5f) continue;
    boxes.emplace_back((row[0] - row[2] / 2 - offset.x) / r, (row[1] - row[3] / 2 - offset.y) / r, row[2] / r, row[3] / r);
  }
  return boxes;
}

TEST(YoloHeadResize, TheBundledExportIsRecognisedAndItsOwnSizeChangesNothing) {
  TKGSLAM_REQUIRE_SHARED();
  const cv::Mat img = cv::imread((test::sharedDir() / "datasets/people/bus.jpg").string());
  ASSERT_FALSE(img.empty());
  cv::dnn::Net original = loadModel(), resized = loadModel();
  EXPECT_EQ(dynamic::yoloHeadExportSize(original), 640);
  ASSERT_TRUE(dynamic::resizeYoloHead(resized, cv::Size(640, 640)));
  float r = 0;
  cv::Point offset;
  const cv::Mat a = run(original, img, {640, 640}, &r, &offset), b = run(resized, img, {640, 640}, &r, &offset);
  ASSERT_EQ(a.size[1], 25200);
  ASSERT_EQ(b.size[1], 25200);
  EXPECT_EQ(cv::norm(a, b, cv::NORM_INF), 0.0) << "the regenerated grids and anchors are the export's own";
}

TEST(YoloHeadResize, AVgaFrameRunsAt640x480WithTheSamePeople) {
  TKGSLAM_REQUIRE_SHARED();
  const cv::Mat img =
      cv::imread((test::sharedDir() / "datasets/people/fr3_walking_halfsphere_1341846434.710184.png").string());
  ASSERT_EQ(img.size(), cv::Size(640, 480));
  cv::dnn::Net square = loadModel(), fitted = loadModel();
  ASSERT_TRUE(dynamic::resizeYoloHead(fitted, cv::Size(640, 480)));
  float r_square = 0, r_fitted = 0;
  cv::Point o_square, o_fitted;
  const cv::Mat out_square = run(square, img, {640, 640}, &r_square, &o_square);
  const cv::Mat out_fitted = run(fitted, img, {640, 480}, &r_fitted, &o_fitted);
  EXPECT_EQ(out_fitted.size[1], 3 * (80 * 60 + 40 * 30 + 20 * 15)) << "3 anchors on each cell of the 3 levels";
  EXPECT_EQ(o_fitted, cv::Point(0, 0)) << "no letterbox padding";
  // Both people of the frame (measured: scores 0.7-0.84 either way), in the same place.
  const auto expected = persons(out_square, r_square, o_square), found = persons(out_fitted, r_fitted, o_fitted);
  ASSERT_FALSE(expected.empty());
  ASSERT_FALSE(found.empty());
  for (const auto& e : expected) {
    float best = 0;
    for (const auto& f : found) best = std::max(best, dynamic::iou(e, f));
    EXPECT_GE(best, 0.8f) << "person at " << e;
  }
}

TEST(YoloHeadResize, RefusesWhatItCannotDoAndLeavesTheNetAsItWas) {
  TKGSLAM_REQUIRE_SHARED();
  cv::dnn::Net net = loadModel();
  EXPECT_FALSE(dynamic::resizeYoloHead(net, cv::Size(640, 470))) << "not a multiple of 32";
  EXPECT_FALSE(dynamic::resizeYoloHead(net, cv::Size(0, 0)));
  const cv::Mat img(480, 640, CV_8UC3, cv::Scalar(30, 60, 90));
  float r = 0;
  cv::Point offset;
  EXPECT_EQ(run(net, img, {640, 640}, &r, &offset).size[1], 25200) << "still the export's head";

  // A net that is not a YOLOv5 export.
  cv::dnn::Net other;
  cv::dnn::LayerParams relu;
  other.addLayerToPrev("relu", "ReLU", relu);
  EXPECT_EQ(dynamic::yoloHeadExportSize(other), 0);
  EXPECT_FALSE(dynamic::resizeYoloHead(other, cv::Size(320, 256)));
}

}  // namespace
}  // namespace tkgslam
