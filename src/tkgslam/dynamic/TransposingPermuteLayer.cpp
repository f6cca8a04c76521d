#include "tkgslam/dynamic/TransposingPermuteLayer.h"

#include <string>

#include <opencv2/core.hpp>
#include <opencv2/dnn/all_layers.hpp>
#include <opencv2/dnn/layer.hpp>

namespace tkgslam::dynamic {

TransposeBlocks transposeBlocks(const std::vector<int>& order, const std::vector<int>& shape) {
  const int n = int(order.size());
  if (n != int(shape.size())) return {};
  int k = 0;
  while (k < n && order[k] == k) ++k;
  if (k == n) return {};  // identity
  const int m = order[k];
  if (m <= k) return {};
  // Expected tail: m, m+1, ..., n-1, k, k+1, ..., m-1.
  for (int i = k; i < n; ++i) {
    const int from = i - k + m;
    if (order[i] != (from < n ? from : from - n + k)) return {};
  }
  TransposeBlocks blocks{1, 1, 1};
  for (int i = 0; i < k; ++i) blocks.batch *= size_t(shape[i]);
  for (int i = k; i < m; ++i) blocks.rows *= size_t(shape[i]);
  for (int i = m; i < n; ++i) blocks.cols *= size_t(shape[i]);
  return blocks;
}

namespace {

class TransposingPermuteLayer : public cv::dnn::Layer {
 public:
  explicit TransposingPermuteLayer(cv::dnn::LayerParams& params) : opencv_(cv::dnn::PermuteLayer::create(params)) {
    setParamsFrom(params);
    if (params.has("order")) {
      const cv::dnn::DictValue& order = params.get("order");
      for (int i = 0; i < order.size(); ++i) order_.push_back(order.get<int>(i));
    }
  }

  bool getMemoryShapes(const std::vector<cv::dnn::MatShape>& inputs, const int required_outputs,
                       std::vector<cv::dnn::MatShape>& outputs,
                       std::vector<cv::dnn::MatShape>& internals) const override {
    return opencv_->getMemoryShapes(inputs, required_outputs, outputs, internals);
  }

  // OpenCV calls this whenever the input shape changes: the blocks are worked out once per shape.
  void finalize(cv::InputArrayOfArrays inputs_arr, cv::OutputArrayOfArrays outputs_arr) override {
    opencv_->finalize(inputs_arr, outputs_arr);
    std::vector<cv::Mat> inputs, outputs;
    inputs_arr.getMatVector(inputs);
    outputs_arr.getMatVector(outputs);
    blocks_ = {};
    if (inputs.size() == 1 && outputs.size() == 1 && inputs[0].type() == CV_32F && outputs[0].type() == CV_32F &&
        inputs[0].isContinuous() && outputs[0].isContinuous() && outputs[0].total() == inputs[0].total()) {
      blocks_ = transposeBlocks(order_, std::vector<int>(inputs[0].size.p, inputs[0].size.p + inputs[0].dims));
    }
  }

  void forward(cv::InputArrayOfArrays inputs_arr, cv::OutputArrayOfArrays outputs_arr,
               cv::OutputArrayOfArrays internals_arr) override {
    if (blocks_.batch == 0) {
      opencv_->forward(inputs_arr, outputs_arr, internals_arr);
      return;
    }
    std::vector<cv::Mat> inputs, outputs;
    inputs_arr.getMatVector(inputs);
    outputs_arr.getMatVector(outputs);
    const size_t block = blocks_.rows * blocks_.cols;
    const float* src = inputs[0].ptr<float>();
    float* dst = outputs[0].ptr<float>();
    for (size_t b = 0; b < blocks_.batch; ++b) {
      const cv::Mat from(int(blocks_.rows), int(blocks_.cols), CV_32F, const_cast<float*>(src + b * block));
      cv::Mat to(int(blocks_.cols), int(blocks_.rows), CV_32F, dst + b * block);
      cv::transpose(from, to);
    }
  }

 private:
  cv::Ptr<cv::dnn::Layer> opencv_;  // OpenCV's own Permute: shapes, and the permutations not done here
  std::vector<int> order_;
  TransposeBlocks blocks_;  // of the shape last finalized; batch 0: OpenCV's layer does it
};

}  // namespace

cv::Ptr<cv::dnn::Layer> createTransposingPermuteLayer(cv::dnn::LayerParams& params) {
  return cv::Ptr<cv::dnn::Layer>(new TransposingPermuteLayer(params));
}

}  // namespace tkgslam::dynamic
