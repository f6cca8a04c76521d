#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include <opencv2/dnn.hpp>

#include <gtest/gtest.h>

#include "TestSupport.h"
#include "tkgslam/dynamic/OnnxLoader.h"
#include "tkgslam/dynamic/OnnxSiluFusion.h"
#include "tkgslam/dynamic/ProtobufWire.h"
#include "tkgslam/dynamic/VectorSigmoidLayer.h"

namespace tkgslam {
namespace {

using dynamic::WireField;

// Small ONNX models written field by field (onnx.proto3's field numbers).
std::string varintField(std::uint32_t number, std::uint64_t value) {
  std::string out;
  dynamic::appendVarint(out, std::uint64_t(number) << 3);
  dynamic::appendVarint(out, value);
  return out;
}

std::string bytesField(std::uint32_t number, const std::string& payload) {
  std::string out;
  dynamic::appendLengthDelimited(out, number, payload);
  return out;
}

std::string node(const std::vector<std::string>& inputs, const std::string& output, const std::string& op_type,
                 const std::string& attributes = "") {
  std::string n;
  for (const auto& input : inputs) n += bytesField(1, input);
  n += bytesField(2, output) + bytesField(3, op_type + "_" + output) + bytesField(4, op_type) + attributes;
  return bytesField(1, n);  // GraphProto.node
}

// A float tensor's ValueInfoProto.
std::string valueInfo(std::uint32_t field, const std::string& name, const std::vector<int>& dims) {
  std::string shape;
  for (int d : dims) shape += bytesField(1, varintField(1, std::uint64_t(d)));
  const std::string tensor = varintField(1, 1) + bytesField(2, shape);
  return bytesField(field, bytesField(1, name) + bytesField(2, bytesField(1, tensor)));
}

std::string initializer(const std::string& name, const std::vector<int>& dims, const std::vector<float>& values) {
  std::string t;
  for (int d : dims) t += varintField(1, std::uint64_t(d));
  t += varintField(2, 1) + bytesField(8, name) +
       bytesField(9, std::string(reinterpret_cast<const char*>(values.data()), values.size() * sizeof(float)));
  return bytesField(5, t);
}

std::vector<uchar> model(const std::string& graph) {
  const std::string m = varintField(1, 7) + bytesField(8, varintField(2, 13)) + bytesField(7, graph);
  return std::vector<uchar>(m.begin(), m.end());
}

// The graph's nodes as (op_type, inputs..., "->", output).
std::vector<std::vector<std::string>> nodesOf(const std::vector<uchar>& bytes) {
  std::vector<WireField> fields, graph, node;
  const std::string_view m(reinterpret_cast<const char*>(bytes.data()), bytes.size());
  EXPECT_TRUE(dynamic::splitWireFields(m, fields));
  std::vector<std::vector<std::string>> nodes;
  for (const auto& f : fields) {
    if (f.number != 7) continue;
    EXPECT_TRUE(dynamic::splitWireFields(f.payload, graph));
    for (const auto& g : graph) {
      if (g.number != 1) continue;
      EXPECT_TRUE(dynamic::splitWireFields(g.payload, node));
      std::vector<std::string> inputs, description;
      std::string output, op_type;
      for (const auto& n : node) {
        if (n.number == 1) inputs.emplace_back(n.payload);
        if (n.number == 2) output = n.payload;
        if (n.number == 4) op_type = n.payload;
      }
      description.push_back(op_type);
      description.insert(description.end(), inputs.begin(), inputs.end());
      description.push_back("->");
      description.push_back(output);
      nodes.push_back(description);
    }
  }
  return nodes;
}

using Nodes = std::vector<std::vector<std::string>>;

TEST(OnnxSiluFusion, FusesEachSigmoidMulPairAndCopiesEverythingElse) {
  const std::string io = valueInfo(11, "x", {1, 2, 3, 4}) + valueInfo(12, "y", {1, 2, 3, 4});
  const auto original = model(node({"x"}, "s", "Sigmoid") + node({"s", "x"}, "y", "Mul") + bytesField(2, "g") + io);
  const auto result = dynamic::fuseSiluNodes(original, "Silu");
  EXPECT_EQ(result.fused, 1);
  EXPECT_EQ(nodesOf(result.model), (Nodes{{"Silu", "x", "->", "y"}}));
  // The same model around the one node: ir_version and opset as they were.
  std::vector<WireField> a, b;
  ASSERT_TRUE(dynamic::splitWireFields({reinterpret_cast<const char*>(result.model.data()), result.model.size()}, a));
  ASSERT_TRUE(dynamic::splitWireFields({reinterpret_cast<const char*>(original.data()), original.size()}, b));
  ASSERT_EQ(a.size(), b.size());
  EXPECT_EQ(a[0].encoded, b[0].encoded);
  EXPECT_EQ(a[1].encoded, b[1].encoded);
  EXPECT_EQ(dynamic::fuseSiluNodes(result.model, "Silu").fused, 0);  // nothing left to fuse
}

TEST(OnnxSiluFusion, LeavesPairsWhoseSigmoidIsNeededElsewhere) {
  const std::string graph = node({"a"}, "s1", "Sigmoid") + node({"a", "s1"}, "y1", "Mul") +  // fused
                            node({"b"}, "s2", "Sigmoid") + node({"b", "s2"}, "y2", "Mul") +  // s2 is an output
                            node({"c"}, "s3", "Sigmoid") + node({"c", "s3"}, "y3", "Mul") +
                            node({"s3"}, "z3", "Relu") +                                       // s3 used twice
                            node({"d"}, "s4", "Sigmoid") + node({"e", "s4"}, "y4", "Mul") +  // another x
                            node({"f"}, "s5", "Sigmoid", bytesField(7, "com.example")) +
                            node({"f", "s5"}, "y5", "Mul") +  // not ONNX's Sigmoid
                            valueInfo(12, "s2", {1});
  const auto result = dynamic::fuseSiluNodes(model(graph), "Silu");
  EXPECT_EQ(result.fused, 1);
  const Nodes nodes = nodesOf(result.model);
  ASSERT_EQ(nodes.size(), 10u);
  EXPECT_EQ(nodes[0], (std::vector<std::string>{"Silu", "a", "->", "y1"}));
  EXPECT_EQ(nodes[1], (std::vector<std::string>{"Sigmoid", "b", "->", "s2"}));
  EXPECT_EQ(nodes[9], (std::vector<std::string>{"Mul", "f", "s5", "->", "y5"}));

  // Control flow: a subgraph may read s without naming it, so nothing is fused.
  const auto loop = model(node({"a"}, "s", "Sigmoid") + node({"a", "s"}, "y", "Mul") + node({"n"}, "l", "Loop"));
  EXPECT_EQ(dynamic::fuseSiluNodes(loop, "Silu").fused, 0);
}

TEST(OnnxSiluFusion, AModelItCannotReadComesBackUnchanged) {
  const auto good = model(node({"x"}, "s", "Sigmoid") + node({"x", "s"}, "y", "Mul"));
  for (size_t cut : {size_t(0), size_t(3), good.size() / 2, good.size() - 1}) {
    const std::vector<uchar> truncated(good.begin(), good.begin() + long(cut));
    const auto result = dynamic::fuseSiluNodes(truncated, "Silu");
    EXPECT_EQ(result.fused, 0) << cut;
    EXPECT_EQ(result.model, truncated) << cut;
  }
  const std::string text = "not a model at all";
  const std::vector<uchar> garbage(text.begin(), text.end());
  EXPECT_EQ(dynamic::fuseSiluNodes(garbage, "Silu").model, garbage);
  const auto two_graphs = model(node({"x"}, "s", "Sigmoid") + node({"x", "s"}, "y", "Mul"));
  std::vector<uchar> doubled = two_graphs;
  doubled.insert(doubled.end(), two_graphs.begin() + 4, two_graphs.end());  // a second graph field
  EXPECT_EQ(dynamic::fuseSiluNodes(doubled, "Silu").fused, 0);
}

TEST(OnnxSiluFusion, TheFusedModelRunsInOpenCvWithTheSameValues) {
  const std::string io = valueInfo(11, "x", {1, 2, 3, 5}) + valueInfo(12, "y", {1, 2, 3, 5});
  const auto silu_only = model(node({"x"}, "s", "Sigmoid") + node({"s", "x"}, "y", "Mul") + io);
  std::vector<float> values(30);
  for (int i = 0; i < 30; ++i) values[i] = -7.f + 0.5f * float(i);
  const int shape[] = {1, 2, 3, 5};
  const cv::Mat input(4, shape, CV_32F, values.data());

  cv::dnn::Net net = dynamic::readOnnxWithFastLayers(silu_only);
  int fused_layers = 0, pairs = 0;  // (OpenCV adds an Identity layer for the output's name)
  for (const auto& name : net.getLayerNames()) {
    const std::string type = net.getLayer(net.getLayerId(name))->type;
    fused_layers += type == dynamic::kFusedSiluType;
    pairs += type == "Sigmoid" || type == "Eltwise" || type == "NaryEltwise";
  }
  EXPECT_EQ(fused_layers, 1);
  EXPECT_EQ(pairs, 0);
  net.setInput(input);
  const cv::Mat y = net.forward();
  std::vector<float> expected(30);
  dynamic::vectorSigmoid(values.data(), expected.data(), 30);
  for (int i = 0; i < 30; ++i) EXPECT_EQ(y.ptr<float>()[i], values[i] * expected[i]) << i;

  // After a convolution, which takes the SiLU in as its activation: OpenCV's unfused model's values.
  const std::string conv =
      node({"x", "w", "b"}, "c", "Conv",
           bytesField(5, bytesField(1, "kernel_shape") + varintField(8, 1) + varintField(8, 1) + varintField(20, 7))) +
      node({"c"}, "s", "Sigmoid") + node({"c", "s"}, "y", "Mul") +
      initializer("w", {2, 2, 1, 1}, {1.5f, -0.5f, 0.25f, 2.f}) + initializer("b", {2}, {0.1f, -0.3f}) + io;
  const auto conv_model = model(conv);
  EXPECT_EQ(dynamic::fuseSiluNodes(conv_model, "Silu").fused, 1);
  cv::dnn::Net ours = dynamic::readOnnxWithFastLayers(conv_model);
  cv::dnn::Net opencv = cv::dnn::readNetFromONNX(conv_model);
  ours.setInput(input);
  const cv::Mat a = ours.forward().clone();
  opencv.setInput(input);
  const cv::Mat b = opencv.forward().clone();
  ASSERT_EQ(a.total(), 30u);
  ASSERT_EQ(b.total(), 30u);
  for (int i = 0; i < 30; ++i) {
    const int k = i / 15;  // the output channel
    const float c = (k == 0 ? 1.5f * values[i % 15] - 0.5f * values[15 + i % 15]
                            : 0.25f * values[i % 15] + 2.f * values[15 + i % 15]) +
                    (k == 0 ? 0.1f : -0.3f);
    const float silu = c / (1.f + std::exp(-c));
    EXPECT_NEAR(a.ptr<float>()[i], silu, 1e-5f * (1.f + std::abs(silu))) << i;
    EXPECT_NEAR(a.ptr<float>()[i], b.ptr<float>()[i], 1e-5f * (1.f + std::abs(silu))) << i;
  }
}

}  // namespace
}  // namespace tkgslam
