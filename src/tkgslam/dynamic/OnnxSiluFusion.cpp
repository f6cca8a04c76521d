#include "tkgslam/dynamic/OnnxSiluFusion.h"

#include <deque>
#include <map>
#include <optional>
#include <set>
#include <string_view>

#include "tkgslam/dynamic/ProtobufWire.h"

namespace tkgslam::dynamic {

namespace {

// Field numbers of onnx.proto3.
constexpr std::uint32_t kModelGraph = 7;
constexpr std::uint32_t kGraphNode = 1;
constexpr std::uint32_t kGraphOutput = 12;
constexpr std::uint32_t kValueInfoName = 1;
constexpr std::uint32_t kNodeInput = 1;
constexpr std::uint32_t kNodeOutput = 2;
constexpr std::uint32_t kNodeName = 3;
constexpr std::uint32_t kNodeOpType = 4;
constexpr std::uint32_t kNodeAttribute = 5;
constexpr std::uint32_t kNodeDomain = 7;

struct Node {
  std::vector<std::string_view> inputs, outputs;
  std::string_view name, op_type, domain;
  bool has_attributes = false;
};

std::optional<Node> parseNode(const WireField& field) {
  std::vector<WireField> fields;
  if (field.type != WireField::kLengthDelimited || !splitWireFields(field.payload, fields)) return std::nullopt;
  Node node;
  for (const WireField& f : fields) {
    const bool text = f.type == WireField::kLengthDelimited;
    if (f.number == kNodeInput && text) node.inputs.push_back(f.payload);
    if (f.number == kNodeOutput && text) node.outputs.push_back(f.payload);
    if (f.number == kNodeName && text) node.name = f.payload;
    if (f.number == kNodeOpType && text) node.op_type = f.payload;
    if (f.number == kNodeDomain && text) node.domain = f.payload;
    if (f.number == kNodeAttribute) node.has_attributes = true;
  }
  return node;
}

bool isStandardOp(const Node& node, std::string_view op_type) {
  return node.op_type == op_type && (node.domain.empty() || node.domain == "ai.onnx") && !node.has_attributes;
}

// A rewritten graph as the pieces it is made of, in order: views into the model's bytes (most of
// it: the weights are not copied) and the fused nodes, which `owned` holds (one per pair fused).
struct GraphPieces {
  std::vector<std::string_view> pieces;
  std::deque<std::string> owned;  // a deque: its strings stay where they are as it grows
  size_t size = 0;
  void add(std::string_view piece) {
    pieces.push_back(piece);
    size += piece.size();
  }
};

// The rewritten graph, or nothing if it cannot be read or has nothing to fuse.
std::optional<GraphPieces> fuseInGraph(std::string_view graph, const std::string& op_type) {
  std::vector<WireField> fields;
  if (!splitWireFields(graph, fields)) return std::nullopt;
  std::vector<Node> nodes;
  std::set<std::string_view> graph_outputs;
  for (const WireField& field : fields) {
    if (field.number == kGraphNode) {
      auto node = parseNode(field);
      if (!node) return std::nullopt;
      // Subgraphs see the outer graph's values without listing them as inputs: leave such graphs alone.
      if (node->op_type == "If" || node->op_type == "Loop" || node->op_type == "Scan") return std::nullopt;
      nodes.push_back(std::move(*node));
    } else if (field.number == kGraphOutput) {
      std::vector<WireField> info;
      if (field.type != WireField::kLengthDelimited || !splitWireFields(field.payload, info)) return std::nullopt;
      for (const WireField& f : info) {
        if (f.number == kValueInfoName && f.type == WireField::kLengthDelimited) graph_outputs.insert(f.payload);
      }
    }
  }
  std::map<std::string_view, int> uses;  // value name -> how many node inputs read it
  for (const Node& node : nodes) {
    for (std::string_view input : node.inputs) ++uses[input];
  }
  std::map<std::string_view, size_t> sigmoid_of;  // a Sigmoid's output -> that node's index
  for (size_t i = 0; i < nodes.size(); ++i) {
    const Node& n = nodes[i];
    if (isStandardOp(n, "Sigmoid") && n.inputs.size() == 1 && n.outputs.size() == 1 && n.inputs[0] != n.outputs[0] &&
        uses[n.outputs[0]] == 1 && !graph_outputs.count(n.outputs[0])) {
      sigmoid_of[n.outputs[0]] = i;
    }
  }
  std::map<size_t, size_t> mul_of;  // Sigmoid index -> its Mul's index
  for (size_t i = 0; i < nodes.size(); ++i) {
    const Node& m = nodes[i];
    if (!isStandardOp(m, "Mul") || m.inputs.size() != 2 || m.outputs.size() != 1) continue;
    for (int k = 0; k < 2; ++k) {
      const auto s = sigmoid_of.find(m.inputs[k]);
      if (s != sigmoid_of.end() && s->second < i && nodes[s->second].inputs[0] == m.inputs[1 - k]) {
        mul_of[s->second] = i;
        break;
      }
    }
  }
  if (mul_of.empty()) return std::nullopt;

  std::set<size_t> dropped;
  for (const auto& [sigmoid, mul] : mul_of) dropped.insert(mul);
  GraphPieces out;
  size_t node_index = 0;
  for (const WireField& field : fields) {
    if (field.number != kGraphNode) {
      out.add(field.encoded);
      continue;
    }
    const size_t i = node_index++;
    if (dropped.count(i)) continue;
    const auto fuse = mul_of.find(i);
    if (fuse == mul_of.end()) {
      out.add(field.encoded);
      continue;
    }
    const Node& sigmoid = nodes[i];
    std::string node;
    appendLengthDelimited(node, kNodeInput, sigmoid.inputs[0]);
    appendLengthDelimited(node, kNodeOutput, nodes[fuse->second].outputs[0]);
    if (!sigmoid.name.empty()) appendLengthDelimited(node, kNodeName, sigmoid.name);
    appendLengthDelimited(node, kNodeOpType, op_type);
    appendLengthDelimited(out.owned.emplace_back(), kGraphNode, node);
    out.add(out.owned.back());
  }
  return out;
}

}  // namespace

SiluFusion fuseSiluNodes(const std::vector<uchar>& model, const std::string& op_type) {
  SiluFusion result;
  const std::string_view bytes(reinterpret_cast<const char*>(model.data()), model.size());
  std::vector<WireField> fields;
  std::optional<GraphPieces> graph;
  if (splitWireFields(bytes, fields)) {
    for (const WireField& field : fields) {
      // A model has one graph; with more (malformed) or none, leave it to OpenCV.
      if (field.number == kModelGraph && field.type == WireField::kLengthDelimited && !graph) {
        graph = fuseInGraph(field.payload, op_type);
        if (!graph) break;
      } else if (field.number == kModelGraph) {
        graph.reset();
        break;
      }
    }
  }
  if (!graph) {
    result.model = model;
    return result;
  }
  // Written once, straight into the result (the model is mostly weights: ~8 MB for YOLOv5n).
  std::vector<uchar>& out = result.model;
  out.reserve(model.size());
  const auto append = [&out](std::string_view bytes) { out.insert(out.end(), bytes.begin(), bytes.end()); };
  for (const WireField& field : fields) {
    if (field.number != kModelGraph) {
      append(field.encoded);
      continue;
    }
    std::string key_and_length;
    appendVarint(key_and_length, (std::uint64_t(kModelGraph) << 3) | WireField::kLengthDelimited);
    appendVarint(key_and_length, graph->size);
    append(key_and_length);
    for (std::string_view piece : graph->pieces) append(piece);
  }
  result.fused = int(graph->owned.size());
  return result;
}

}  // namespace tkgslam::dynamic
