#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include <opencv2/dnn.hpp>

#include <gtest/gtest.h>

#include "tkgslam/dynamic/VectorSigmoidLayer.h"

namespace tkgslam {
namespace {

using dynamic::vectorSigmoid;

TEST(VectorSigmoidLayer, MatchesTheExactSigmoidWithinOneMillionth) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<float> wide(-100.f, 100.f), narrow(-6.f, 6.f);
  std::vector<float> x;
  for (int i = 0; i < 50000; ++i) x.push_back(i % 2 ? wide(rng) : narrow(rng));
  for (float v : {0.f, -0.f, 1e-8f, -1e-8f, 87.f, -87.f, 88.f, -88.f, 88.5f, -88.5f, 1e30f, -1e30f}) x.push_back(v);
  x.push_back(3.f);  // 50013 values: not a multiple of the eight lanes, the tail goes through the same code
  std::vector<float> y(x.size());
  vectorSigmoid(x.data(), y.data(), x.size());
  double worst = 0;
  for (size_t i = 0; i < x.size(); ++i) {
    const double exact = 1.0 / (1.0 + std::exp(-double(x[i])));
    ASSERT_GE(y[i], 0.f) << x[i];
    ASSERT_LE(y[i], 1.f) << x[i];
    if (exact < 1e-37) {
      EXPECT_LT(y[i], 1e-37f) << x[i];
      continue;
    }
    worst = std::max(worst, std::abs(y[i] - exact) / exact);
  }
  EXPECT_LT(worst, 1e-6);
  EXPECT_GT(worst, 0.0);  // a polynomial, not the C library: it is not exact everywhere
  EXPECT_EQ(y[x.size() - 13], 0.5f);  // sigmoid(0)
}

TEST(VectorSigmoidLayer, InfinitiesSaturateNanStaysNanInPlaceIsTheSame) {
  const float inf = std::numeric_limits<float>::infinity();
  std::vector<float> x{inf, -inf, std::nanf(""), 2.f, -2.f, 0.5f, 10.f, -10.f, 1.f};
  std::vector<float> y(x.size());
  vectorSigmoid(x.data(), y.data(), x.size());
  EXPECT_EQ(y[0], 1.f);
  EXPECT_LT(y[1], 1e-37f);
  EXPECT_TRUE(std::isnan(y[2]));
  std::vector<float> in_place = x;
  vectorSigmoid(in_place.data(), in_place.data(), in_place.size());
  for (size_t i = 3; i < x.size(); ++i) EXPECT_EQ(in_place[i], y[i]);
  // Each value is computed on its own: the same value gives the same bits wherever it sits.
  std::vector<float> shifted(x.begin() + 3, x.end()), z(shifted.size());
  vectorSigmoid(shifted.data(), z.data(), z.size());
  for (size_t i = 0; i < z.size(); ++i) EXPECT_EQ(z[i], y[i + 3]);
}

TEST(VectorSigmoidLayer, LayerRunsTheFunctionOverEveryInput) {
  cv::dnn::LayerParams params;
  params.type = "Sigmoid";
  params.name = "s";
  const cv::Ptr<cv::dnn::Layer> layer = dynamic::createVectorSigmoidLayer(params);
  const std::vector<int> shape{1, 3, 70, 90};  // 18900 values: several of the layer's stripes
  std::vector<cv::Mat> inputs{cv::Mat(shape, CV_32F)}, outputs{cv::Mat(shape, CV_32F)}, internals;
  cv::randu(inputs[0], -20.f, 20.f);
  layer->finalize(cv::InputArrayOfArrays(inputs), cv::OutputArrayOfArrays(outputs));
  layer->forward(cv::InputArrayOfArrays(inputs), cv::OutputArrayOfArrays(outputs),
                 cv::OutputArrayOfArrays(internals));
  std::vector<float> expected(inputs[0].total());
  vectorSigmoid(inputs[0].ptr<float>(), expected.data(), expected.size());
  for (size_t i = 0; i < expected.size(); ++i) ASSERT_EQ(outputs[0].ptr<float>()[i], expected[i]) << i;
}

}  // namespace
}  // namespace tkgslam
