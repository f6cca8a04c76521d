#include "tkgslam/dynamic/YoloHeadResize.h"

#include <functional>
#include <map>
#include <string>
#include <vector>

#include <opencv2/dnn/all_layers.hpp>

namespace tkgslam::dynamic {

namespace {

constexpr int kMaxStride = 32;

/// One detection level of the head, as exported (native grid gh x gh) and the layers to rewrite.
struct Level {
  int grid_size = 0;  // cells per side at the export size
  int stride = 0;
  int anchors = 0;
  cv::Ptr<cv::dnn::Layer> grid;          // Const 1 x anchors x gh x gh x 2: cell offsets
  cv::Ptr<cv::dnn::Layer> anchor_grid;   // Scale weights: anchor sizes repeated over the cells
  std::vector<cv::dnn::ReshapeLayer*> reshapes;
};

/// Whether `blob` (1 x anchors x g x g x 2) holds the offsets (x - 0.5, y - 0.5) of every cell.
bool isCellOffsetGrid(const cv::Mat& blob) {
  const int na = blob.size[1], gh = blob.size[2], gw = blob.size[3];
  const float* v = blob.ptr<float>();
  for (int a = 0; a < na; ++a)
    for (int y = 0; y < gh; ++y)
      for (int x = 0; x < gw; ++x, v += 2)
        if (v[0] != float(x) - 0.5f || v[1] != float(y) - 0.5f) return false;
  return true;
}

/// Whether the weights (anchors x cells x 2 values) repeat one width and height per anchor.
bool isRepeatedPerAnchor(const cv::Mat& blob, int anchors) {
  const size_t per_anchor = blob.total() / size_t(anchors);
  const float* v = blob.ptr<float>();
  for (int a = 0; a < anchors; ++a) {
    const float* first = v + a * per_anchor;
    for (size_t k = 0; k < per_anchor; k += 2)
      if (first[k] != first[0] || first[k + 1] != first[1]) return false;
  }
  return true;
}

/// The head's levels, finest first, when it is the one recognised; empty otherwise.
std::vector<Level> findHead(cv::dnn::Net& net) {
  std::map<int, Level, std::greater<int>> levels;  // by native grid size, finest first
  std::vector<cv::Ptr<cv::dnn::Layer>> scales;
  std::vector<cv::dnn::ReshapeLayer*> reshapes;
  for (const std::string& name : net.getLayerNames()) {
    cv::Ptr<cv::dnn::Layer> layer = net.getLayer(net.getLayerId(name));
    if (!layer) continue;
    if (layer->type == "Const" && layer->blobs.size() == 1) {
      const cv::Mat& b = layer->blobs[0];
      if (b.dims != 5 || b.type() != CV_32F || b.size[0] != 1 || b.size[1] < 1 || b.size[4] != 2 ||
          b.size[2] < 1 || b.size[2] != b.size[3]) {
        continue;
      }
      if (!isCellOffsetGrid(b)) continue;
      if (levels.count(b.size[2])) return {};  // two grids of one size: not the head we know
      Level& level = levels[b.size[2]];
      level.grid_size = b.size[2];
      level.anchors = b.size[1];
      level.grid = layer;
    } else if (layer->type == "Scale" && layer->blobs.size() == 1) {
      scales.push_back(layer);
    } else if (auto* reshape = dynamic_cast<cv::dnn::ReshapeLayer*>(layer.get())) {
      reshapes.push_back(reshape);
    }
  }
  if (levels.size() != 3) return {};
  const int export_size = levels.begin()->first * 8;
  std::vector<Level> head;
  for (auto& [g, level] : levels) {
    level.stride = export_size / g;
    if (g * level.stride != export_size || level.stride != 8 << head.size()) return {};
    const size_t cells = size_t(g) * size_t(g);
    for (const auto& s : scales) {
      const cv::Mat& b = s->blobs[0];
      if (b.type() == CV_32F && b.total() == size_t(level.anchors) * cells * 2 && isRepeatedPerAnchor(b, level.anchors)) {
        if (level.anchor_grid) return {};
        level.anchor_grid = s;
      }
    }
    int per_cell_reshapes = 0;
    for (auto* r : reshapes) {
      const cv::dnn::MatShape& d = r->newShapeDesc;
      const bool per_cell = d.size() == 5 && d[0] == 1 && d[1] == level.anchors && d[3] == g && d[4] == g;
      const bool flat = d.size() == 3 && d[0] == 1 && size_t(d[1]) == size_t(level.anchors) * cells;
      if (per_cell) ++per_cell_reshapes;
      if (per_cell || flat) level.reshapes.push_back(r);
    }
    // The flattening reshape may name its row count (rewritten) or leave it to OpenCV (-1).
    if (!level.anchor_grid || per_cell_reshapes != 1 || level.reshapes.size() > 2) return {};
    head.push_back(level);
  }
  return head;
}

}  // namespace

int yoloHeadExportSize(cv::dnn::Net& net) {
  const std::vector<Level> head = findHead(net);
  return head.empty() ? 0 : head.front().grid_size * head.front().stride;
}

bool resizeYoloHead(cv::dnn::Net& net, cv::Size input) {
  if (input.width <= 0 || input.height <= 0 || input.width % kMaxStride != 0 || input.height % kMaxStride != 0) {
    return false;
  }
  std::vector<Level> head = findHead(net);
  if (head.empty()) return false;
  // Everything recognised: rewrite.
  for (Level& level : head) {
    const int gw = input.width / level.stride, gh = input.height / level.stride, na = level.anchors;
    const int grid_shape[5] = {1, na, gh, gw, 2};
    cv::Mat grid(5, grid_shape, CV_32F);
    float* v = grid.ptr<float>();
    for (int a = 0; a < na; ++a)
      for (int y = 0; y < gh; ++y)
        for (int x = 0; x < gw; ++x) {
          *v++ = float(x) - 0.5f;
          *v++ = float(y) - 0.5f;
        }
    level.grid->blobs[0] = grid;

    const cv::Mat old = level.anchor_grid->blobs[0];
    const size_t old_per_anchor = old.total() / size_t(na), per_anchor = size_t(gh) * size_t(gw) * 2;
    cv::Mat anchor_grid(1, int(size_t(na) * per_anchor), CV_32F);
    for (int a = 0; a < na; ++a) {
      const float* src = old.ptr<float>() + a * old_per_anchor;
      float* dst = anchor_grid.ptr<float>() + a * per_anchor;
      for (size_t k = 0; k < per_anchor; k += 2) {
        dst[k] = src[0];
        dst[k + 1] = src[1];
      }
    }
    level.anchor_grid->blobs[0] = anchor_grid;

    for (auto* r : level.reshapes) {
      cv::dnn::MatShape& d = r->newShapeDesc;
      if (d.size() == 5) {
        d[3] = gh;
        d[4] = gw;
      } else {
        d[1] = na * gh * gw;
      }
    }
  }
  return true;
}

}  // namespace tkgslam::dynamic
