#pragma once
// SiLU, x * sigmoid(x), as one activation layer: the node OnnxSiluFusion.h makes of YOLOv5's
// Sigmoid + Mul pairs. Being an activation layer, OpenCV's convolution applies it to each block of
// its output while that is in cache, instead of two more passes over the whole output. The values
// are those of vectorSigmoid (VectorSigmoidLayer.h) times x, bit for bit what the pair gives.
#include <cstddef>

#include <opencv2/dnn.hpp>

namespace tkgslam::dynamic {

/// y[i] = x[i] * vectorSigmoid(x[i]) for i < n; x and y may be the same array.
void vectorSilu(const float* x, float* y, size_t n);

/// The layer, for LayerParams of any type name (the fused nodes' type).
cv::Ptr<cv::dnn::Layer> createVectorSiluLayer(cv::dnn::LayerParams& params);

}  // namespace tkgslam::dynamic
