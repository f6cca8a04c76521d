#pragma once
// YOLOv5's activation is SiLU, x * sigmoid(x): 57 Sigmoid layers over every convolution's output.
// OpenCV 4.6 computes each value with the C library's expf, one at a time - 12 of the detector's
// 47 ms at 640 x 480 (two threads), 17 of 60 ms on one. This layer evaluates the same function eight
// values at a time (a degree-6 polynomial exp; relative error below 1e-6 of OpenCV's result), with
// AVX2 where the CPU has it, chosen at run time (the build stays baseline x86-64).
#include <cstddef>

#include <opencv2/dnn.hpp>

namespace tkgslam::dynamic {

/// y[i] = 1 / (1 + exp(-x[i])) for i < n; x and y may be the same array. NaN stays NaN; the result is
/// within 1e-6 (relative) of the exact value down to ~1e-38, 0 < y <= 1 for finite x.
void vectorSigmoid(const float* x, float* y, size_t n);

/// A Sigmoid layer (LayerParams of type "Sigmoid") that runs vectorSigmoid over its input.
cv::Ptr<cv::dnn::Layer> createVectorSigmoidLayer(cv::dnn::LayerParams& params);

}  // namespace tkgslam::dynamic
