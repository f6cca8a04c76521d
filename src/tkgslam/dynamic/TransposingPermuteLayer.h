#pragma once
// OpenCV 4.6's Permute layer (ONNX Transpose) moves one element at a time through the strides of
// every axis: the YOLOv5 head's three transposes of 1 x 3 x 85 x gh x gw took 20 of the detector's
// 82 ms (640 x 640, two threads). A permutation that keeps the leading axes and swaps two groups of
// trailing ones is a batch of 2-D transposes, which cv::transpose does in cache-sized blocks: the
// same values, copied, in ~1 ms. This layer takes that path and leaves other permutations to OpenCV.
#include <cstddef>
#include <vector>

#include <opencv2/dnn.hpp>

namespace tkgslam::dynamic {

/// A permutation seen as `batch` transposes of a `rows` x `cols` matrix (row-major, contiguous);
/// batch == 0 when it is not one.
struct TransposeBlocks {
  size_t batch = 0;
  size_t rows = 0;
  size_t cols = 0;
};

/// How `order` (output axis i = input axis order[i]) permutes a blob of `shape`: the axes before the
/// first moved one stay, and the rest must be the group from order[k] to the last axis followed by
/// the group from k to order[k] - 1 (e.g. 0 1 3 4 2: batch 1 x 3, rows = axis 2, cols = axes 3-4).
TransposeBlocks transposeBlocks(const std::vector<int>& order, const std::vector<int>& shape);

/// A Permute layer (LayerParams of type "Permute" with "order") that transposes blocks where it can
/// and runs OpenCV's own Permute otherwise.
cv::Ptr<cv::dnn::Layer> createTransposingPermuteLayer(cv::dnn::LayerParams& params);

}  // namespace tkgslam::dynamic
