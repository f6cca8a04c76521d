#include <cstring>

#include <opencv2/dnn.hpp>
#include <opencv2/dnn/all_layers.hpp>
#include <opencv2/dnn/shape_utils.hpp>

#include <gtest/gtest.h>

#include "tkgslam/dynamic/TransposingPermuteLayer.h"

namespace tkgslam {
namespace {

using dynamic::transposeBlocks;

TEST(TransposingPermuteLayer, RecognisesPermutationsThatAreBatchedTransposes) {
  // The YOLOv5 head: 1 x 3 x 85 x 60 x 80 -> 1 x 3 x 60 x 80 x 85.
  auto b = transposeBlocks({0, 1, 3, 4, 2}, {1, 3, 85, 60, 80});
  EXPECT_EQ(b.batch, 3u);
  EXPECT_EQ(b.rows, 85u);
  EXPECT_EQ(b.cols, 4800u);
  b = transposeBlocks({1, 0}, {4, 7});
  EXPECT_EQ(b.batch, 1u);
  EXPECT_EQ(b.rows, 4u);
  EXPECT_EQ(b.cols, 7u);
  b = transposeBlocks({0, 3, 1, 2}, {2, 3, 4, 5});  // the last axis to the front of the tail
  EXPECT_EQ(b.batch, 2u);
  EXPECT_EQ(b.rows, 12u);
  EXPECT_EQ(b.cols, 5u);
  EXPECT_EQ(transposeBlocks({0, 1, 2}, {2, 3, 4}).batch, 0u);      // identity
  EXPECT_EQ(transposeBlocks({2, 0, 3, 1}, {2, 3, 4, 5}).batch, 0u);  // not two swapped groups
  EXPECT_EQ(transposeBlocks({0, 2, 1, 3}, {2, 3, 4, 5}).batch, 0u);  // swaps inside, keeps the last axis
  EXPECT_EQ(transposeBlocks({0, 2, 1}, {2, 3}).batch, 0u);           // order and shape disagree
}

// Runs one Permute layer on `input` the way OpenCV DNN does: shapes, finalize, forward.
cv::Mat runPermute(const cv::Ptr<cv::dnn::Layer>& layer, const cv::Mat& input) {
  std::vector<cv::dnn::MatShape> in_shapes{cv::dnn::shape(input)}, out_shapes, internal_shapes;
  layer->getMemoryShapes(in_shapes, 1, out_shapes, internal_shapes);
  std::vector<cv::Mat> inputs{input}, outputs{cv::Mat(out_shapes[0], CV_32F)}, internals;
  layer->finalize(cv::InputArrayOfArrays(inputs), cv::OutputArrayOfArrays(outputs));
  layer->forward(cv::InputArrayOfArrays(inputs), cv::OutputArrayOfArrays(outputs), cv::OutputArrayOfArrays(internals));
  return outputs[0];
}

TEST(TransposingPermuteLayer, GivesOpenCvsPermuteToTheBit) {
  const std::vector<std::vector<int>> orders{{0, 1, 3, 4, 2}, {0, 2, 3, 4, 1}, {0, 4, 1, 2, 3}, {3, 0, 4, 1, 2},
                                             {0, 1, 2, 3, 4}, {4, 3, 2, 1, 0}};
  const std::vector<int> shape{2, 3, 5, 4, 6};
  cv::Mat input(shape, CV_32F);
  cv::randu(input, -10.f, 10.f);
  for (const auto& order : orders) {
    cv::dnn::LayerParams params;
    params.type = "Permute";
    params.name = "p";
    params.set("order", cv::dnn::DictValue::arrayInt(order.data(), int(order.size())));
    const cv::Mat ours = runPermute(dynamic::createTransposingPermuteLayer(params), input);
    const cv::Mat opencv = runPermute(cv::dnn::PermuteLayer::create(params), input);
    ASSERT_EQ(cv::dnn::shape(ours), cv::dnn::shape(opencv));
    EXPECT_EQ(std::memcmp(ours.data, opencv.data, ours.total() * sizeof(float)), 0)
        << "order " << order[0] << order[1] << order[2] << order[3] << order[4];
  }
}

}  // namespace
}  // namespace tkgslam
