#pragma once
// What our element-wise layers (VectorSigmoidLayer, VectorSiluLayer) share: a layer that runs one
// function over its input, in place if OpenCV wants.
#include <cstddef>
#include <vector>

#include <opencv2/dnn.hpp>

namespace tkgslam::dynamic {

/// Runs `function`(x, y, n) over each input blob into the output blob of the same index (CV_32F,
/// contiguous, the same number of values; may be the same memory), in tasks of 2^15 values on
/// OpenCV's threads. `function` must give each value independently of where a task starts.
void forwardElementwise(cv::InputArrayOfArrays inputs, cv::OutputArrayOfArrays outputs,
                        void (*function)(const float* x, float* y, size_t n));

/// A layer of OpenCV's class `Base` (cv::dnn::Layer or one derived from it) computing `Function`.
template <class Base, void (*Function)(const float*, float*, size_t)>
class ElementwiseLayer : public Base {
 public:
  explicit ElementwiseLayer(cv::dnn::LayerParams& params) { this->setParamsFrom(params); }

  bool getMemoryShapes(const std::vector<cv::dnn::MatShape>& inputs, const int required_outputs,
                       std::vector<cv::dnn::MatShape>& outputs,
                       std::vector<cv::dnn::MatShape>& internals) const override {
    cv::dnn::Layer::getMemoryShapes(inputs, required_outputs, outputs, internals);
    return true;  // may run in place
  }

  void forward(cv::InputArrayOfArrays inputs, cv::OutputArrayOfArrays outputs, cv::OutputArrayOfArrays) override {
    forwardElementwise(inputs, outputs, Function);
  }
};

}  // namespace tkgslam::dynamic
