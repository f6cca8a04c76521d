#pragma once
// YOLOv5 exports its activation, SiLU = x * sigmoid(x), as two ONNX nodes: Sigmoid(x) and
// Mul(x, sigmoid). OpenCV 4.6 has no rule that joins them, so every convolution's output goes
// through memory twice more, and the convolution cannot apply the activation itself (it does so
// only for a single activation layer that is its only consumer). This rewrites the model's graph
// so that each such pair is one node of our own type, before OpenCV reads it.
#include <string>
#include <vector>

#include <opencv2/core.hpp>

namespace tkgslam::dynamic {

struct SiluFusion {
  std::vector<uchar> model;  ///< the ONNX model's bytes, rewritten
  int fused = 0;             ///< pairs replaced
};

/// `model` (the bytes of an ONNX file) with every pair Sigmoid(x) -> s, Mul(x, s) -> y replaced by
/// one node `op_type`(x) -> y in the Sigmoid's place, where s is used by that Mul only and is not an
/// output of the graph. Everything else is copied byte for byte. A model this cannot read (not a
/// protocol-buffer message, or a graph with control flow whose subgraphs could use s) comes back
/// unchanged with fused = 0, for OpenCV to accept or reject.
SiluFusion fuseSiluNodes(const std::vector<uchar>& model, const std::string& op_type);

}  // namespace tkgslam::dynamic
