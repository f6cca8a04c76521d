#include <cstring>
#include <random>
#include <vector>

#include <opencv2/dnn.hpp>
#include <opencv2/dnn/all_layers.hpp>

#include <gtest/gtest.h>

#include "tkgslam/dynamic/VectorSigmoidLayer.h"
#include "tkgslam/dynamic/VectorSiluLayer.h"

namespace tkgslam {
namespace {

std::vector<float> randomValues(size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<float> value(-12.f, 12.f);
  std::vector<float> x(n);
  for (float& v : x) v = value(rng);
  return x;
}

// What YOLOv5's Sigmoid + Mul pair gives with our Sigmoid layer.
std::vector<float> sigmoidTimesX(const std::vector<float>& x) {
  std::vector<float> y(x.size());
  dynamic::vectorSigmoid(x.data(), y.data(), x.size());
  for (size_t i = 0; i < x.size(); ++i) y[i] *= x[i];
  return y;
}

TEST(VectorSiluLayer, GivesTheSigmoidMulPairsBitsAtAnyLengthAndInPlace) {
  for (size_t n : {size_t(1), size_t(7), size_t(8), size_t(255), size_t(256), size_t(257), size_t(5000)}) {
    const std::vector<float> x = randomValues(n, unsigned(n));
    const std::vector<float> expected = sigmoidTimesX(x);
    std::vector<float> y(n);
    dynamic::vectorSilu(x.data(), y.data(), n);
    EXPECT_EQ(std::memcmp(y.data(), expected.data(), n * sizeof(float)), 0) << n;
    std::vector<float> in_place = x;
    dynamic::vectorSilu(in_place.data(), in_place.data(), n);
    EXPECT_EQ(std::memcmp(in_place.data(), expected.data(), n * sizeof(float)), 0) << n;
  }
  const float x[3] = {0.f, 1.f, -1.f};
  float y[3];
  dynamic::vectorSilu(x, y, 3);
  EXPECT_EQ(y[0], 0.f);
  EXPECT_NEAR(y[1], 0.7310586f, 1e-6f);
  EXPECT_NEAR(y[2], -0.2689414f, 1e-6f);
}

TEST(VectorSiluLayer, AsAConvolutionsActivationItDoesTheChannelsItIsGivenOnly) {
  cv::dnn::LayerParams params;
  params.name = "silu";
  params.type = "TkgslamSiLU";
  const auto layer = dynamic::createVectorSiluLayer(params).dynamicCast<cv::dnn::ActivationLayer>();
  ASSERT_FALSE(layer.empty());  // an activation layer: OpenCV's convolution can take it in

  // Four channels of a 10-value plane; the call does channels 1 and 2, the first 6 values of each.
  std::vector<float> planes = randomValues(40, 9);
  const std::vector<float> expected = sigmoidTimesX(planes);
  std::vector<float> out = planes;
  layer->forwardSlice(planes.data() + 10, out.data() + 10, 6, 10, 1, 3);
  for (int i = 0; i < 40; ++i) {
    const int channel = i / 10, offset = i % 10;
    const bool done = channel >= 1 && channel <= 2 && offset < 6;
    EXPECT_EQ(out[i], done ? expected[i] : planes[i]) << i;
  }

  // The whole-blob path.
  const std::vector<float> x = randomValues(2 * 3 * 70000, 4);  // more than one task's stripe
  const int shape[] = {2, 3, 70000};
  cv::Mat input(3, shape, CV_32F, const_cast<float*>(x.data())), output(3, shape, CV_32F);
  std::vector<cv::Mat> inputs{input}, outputs{output}, internals;
  layer->forward(inputs, outputs, internals);
  const std::vector<float> whole = sigmoidTimesX(x);
  EXPECT_EQ(std::memcmp(output.ptr<float>(), whole.data(), whole.size() * sizeof(float)), 0);
}

}  // namespace
}  // namespace tkgslam
