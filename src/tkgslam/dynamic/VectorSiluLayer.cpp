#include "tkgslam/dynamic/VectorSiluLayer.h"

#include <algorithm>
#include <vector>

#include <opencv2/dnn/all_layers.hpp>

#include "tkgslam/dynamic/ElementwiseLayer.h"
#include "tkgslam/dynamic/VectorSigmoidLayer.h"

namespace tkgslam::dynamic {

namespace {

class VectorSiluLayer : public ElementwiseLayer<cv::dnn::ActivationLayer, vectorSilu> {
 public:
  using ElementwiseLayer::ElementwiseLayer;

  // Called by a convolution that took this layer as its activation: channels cn0 .. cn1 - 1 of one
  // block of its output, `len` values each, `plane` apart.
  void forwardSlice(const float* src, float* dst, int len, size_t plane, int cn0, int cn1) const override {
    for (int c = cn0; c < cn1; ++c, src += plane, dst += plane) vectorSilu(src, dst, size_t(len));
  }
};

}  // namespace

void vectorSilu(const float* x, float* y, size_t n) {
  constexpr size_t kChunk = 256;  // sigmoids on the stack, then the products; x is read before y is written
  float s[kChunk];
  for (size_t begin = 0; begin < n; begin += kChunk) {
    const size_t m = std::min(kChunk, n - begin);
    vectorSigmoid(x + begin, s, m);
    for (size_t i = 0; i < m; ++i) y[begin + i] = x[begin + i] * s[i];
  }
}

cv::Ptr<cv::dnn::Layer> createVectorSiluLayer(cv::dnn::LayerParams& params) {
  return cv::Ptr<cv::dnn::Layer>(new VectorSiluLayer(params));
}

}  // namespace tkgslam::dynamic
