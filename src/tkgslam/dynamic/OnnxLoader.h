#pragma once
// Loading an ONNX model with OpenCV DNN, two of its layer types replaced by faster ones of ours:
// Permute (TransposingPermuteLayer.h: the same values, 20 -> 1 ms in YOLOv5n) and Sigmoid
// (VectorSigmoidLayer.h: within 1e-6 of it, ~2.7x faster); and SiLU written as Sigmoid + Mul made
// one activation layer (OnnxSiluFusion.h, VectorSiluLayer.h), which the convolutions apply.
#include <vector>

#include <opencv2/dnn.hpp>

namespace tkgslam::dynamic {

/// Nodes of this type in a model are our SiLU layer.
extern const char* const kFusedSiluType;

/// cv::dnn::readNetFromONNX on the bytes of an ONNX file, its SiLU pairs fused, with our Permute,
/// Sigmoid and SiLU layers.
/// OpenCV's layer registry is process-wide: it is changed only while the net loads and its layers
/// are created, and restored after (also when loading fails).
cv::dnn::Net readOnnxWithFastLayers(const std::vector<uchar>& model);

}  // namespace tkgslam::dynamic
