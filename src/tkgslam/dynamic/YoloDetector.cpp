#include "tkgslam/dynamic/YoloDetector.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>

#include <fmt/format.h>
#include <opencv2/imgproc.hpp>

#include "tkgslam/common/Error.h"
#include "tkgslam/dynamic/YoloHeadResize.h"

namespace tkgslam::dynamic {

std::vector<int> defaultDynamicClasses() {
  // person; bicycle car motorcycle airplane bus train truck boat; bird cat dog horse sheep cow
  // elephant bear zebra giraffe.
  return {0, 1, 2, 3, 4, 5, 6, 7, 8, 14, 15, 16, 17, 18, 19, 20, 21, 22, 23};
}

YoloDetector::YoloDetector(const DetectorParams& params) : params_(params) {
  if (params_.model.empty()) throw InputError("detector: no model path configured (dynamic.model)");
  if (!std::filesystem::is_regular_file(params_.model)) {
    throw InputError(fmt::format("detector: model file '{}' does not exist", params_.model));
  }
  if (params_.input_size < 64 || params_.input_size > DetectorParams::kMaxInputSize || params_.input_size % 32 != 0) {
    throw InputError(fmt::format("detector: input size {} must be a multiple of 32 from 64 to {}", params_.input_size,
                                 DetectorParams::kMaxInputSize));
  }
  if (!(params_.confidence > 0 && params_.confidence < 1) || !(params_.person_confidence > 0 && params_.person_confidence < 1) ||
      !(params_.nms > 0 && params_.nms <= 1)) {
    throw InputError("detector: confidence thresholds must be in (0, 1) and nms in (0, 1]");
  }
  {
    std::ifstream file(params_.model, std::ios::binary);
    if (!file) throw InputError(fmt::format("detector: cannot read model file '{}'", params_.model));
    model_bytes_.assign(std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>());
    if (model_bytes_.empty()) throw InputError(fmt::format("detector: ONNX model '{}' is empty", params_.model));
  }
  cv::Mat out;
  try {
    net_ = load();
    export_size_ = yoloHeadExportSize(net_);
    // Probe the output shape once so a wrong model fails at start-up, not mid-run.
    prepareNet(cv::Size(params_.input_size, params_.input_size));
    cv::Mat probe(params_.input_size, params_.input_size, CV_8UC3, cv::Scalar(114, 114, 114));
    net_.setInput(cv::dnn::blobFromImage(probe, 1.0 / 255.0, cv::Size(), cv::Scalar(), true, false));
    out = net_.forward();
  } catch (const cv::Exception& e) {
    throw InputError(fmt::format("detector: model '{}' does not load or run at input size {}: {}", params_.model,
                                 params_.input_size, e.what()));
  }
  if (out.dims != 3 || out.size[2] < 6) {
    throw InputError(fmt::format("detector: model '{}' output is not YOLOv5-shaped (1 x N x 5+classes)", params_.model));
  }
  const int num_classes = out.size[2] - 5;
  wanted_.assign(num_classes, 0);
  for (int c : params_.classes) {
    if (c < 0 || c >= num_classes) {
      throw InputError(fmt::format("detector: class id {} outside the model's {} classes", c, num_classes));
    }
    wanted_[c] = 1;
  }
}

cv::dnn::Net YoloDetector::load() const {
  cv::dnn::Net net = cv::dnn::readNetFromONNX(model_bytes_);
  if (net.empty()) throw InputError(fmt::format("detector: ONNX model '{}' is empty", params_.model));
  net.setPreferableBackend(cv::dnn::DNN_BACKEND_OPENCV);
  net.setPreferableTarget(cv::dnn::DNN_TARGET_CPU);
  return net;
}

void YoloDetector::prepareNet(cv::Size input) {
  if (input == net_input_) return;
  if (!net_input_.empty()) net_ = load();  // a net that ran at another size has fused its layers
  if (export_size_ > 0 && input != cv::Size(export_size_, export_size_) && !resizeYoloHead(net_, input)) {
    throw InputError(fmt::format("detector: cannot resize the head of '{}' to {} x {}", params_.model, input.width,
                                 input.height));
  }
  net_input_ = input;
}

cv::Size YoloDetector::inputSize() {
  std::lock_guard<std::mutex> lock(mutex_);
  return net_input_;
}

std::vector<Detection> YoloDetector::detect(const cv::Mat& bgr) { return detectTiles({bgr}).front(); }

std::vector<std::vector<Detection>> YoloDetector::detectTiles(const std::vector<cv::Mat>& images) {
  if (images.empty()) return {};
  for (const auto& bgr : images) {
    if (bgr.empty() || bgr.type() != CV_8UC3) throw InputError("detector: expects 8-bit BGR images");
  }
  const int S = params_.input_size;
  const int grid = int(std::ceil(std::sqrt(double(images.size()) - 1e-9)));
  // The images fill a grid x grid block of equal cells: square cells in an S x S input, or cells
  // of the images' aspect ratio (S / grid on the long side) when the input can be fitted.
  cv::Size cell(S / grid, S / grid), input_size(S, S);
  if (params_.fit_input && export_size_ > 0) {
    cell = cv::Size(0, 0);
    for (const auto& bgr : images) {
      const double r = double(S) / grid / std::max(bgr.cols, bgr.rows);
      cell.width = std::max({cell.width, 1, int(std::lround(bgr.cols * r))});
      cell.height = std::max({cell.height, 1, int(std::lround(bgr.rows * r))});
    }
    const auto roundUp = [](int v) { return (v + 31) / 32 * 32; };
    input_size = cv::Size(roundUp(grid * cell.width), roundUp(grid * cell.height));
  }
  const cv::Point origin((input_size.width - grid * cell.width) / 2, (input_size.height - grid * cell.height) / 2);
  // Each image letterboxed into its cell of the network input.
  struct Placement {
    float r;
    int x0, y0;  // the image's top-left corner in the input
  };
  std::vector<Placement> place;
  cv::Mat input(input_size, CV_8UC3, cv::Scalar(114, 114, 114));
  for (size_t i = 0; i < images.size(); ++i) {
    const cv::Mat& bgr = images[i];
    const float r = std::min(float(cell.width) / bgr.cols, float(cell.height) / bgr.rows);
    const int nw = std::max(1, int(std::lround(bgr.cols * r))), nh = std::max(1, int(std::lround(bgr.rows * r)));
    const int cx = origin.x + int(i % grid) * cell.width, cy = origin.y + int(i / grid) * cell.height;
    const Placement pl{r, cx + (cell.width - nw) / 2, cy + (cell.height - nh) / 2};
    cv::resize(bgr, input(cv::Rect(pl.x0, pl.y0, nw, nh)), cv::Size(nw, nh), 0, 0, cv::INTER_LINEAR);
    place.push_back(pl);
  }
  cv::Mat out;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    prepareNet(input_size);
    net_.setInput(cv::dnn::blobFromImage(input, 1.0 / 255.0, cv::Size(), cv::Scalar(), true, false));
    out = net_.forward();
  }
  const int rows = out.size[1], cols = out.size[2];
  const int num_classes = cols - 5;
  const float min_conf = std::min(params_.confidence, params_.person_confidence);
  // [image][class] candidate boxes (image pixels) and scores.
  std::vector<std::vector<std::vector<cv::Rect2d>>> boxes(images.size(), std::vector<std::vector<cv::Rect2d>>(num_classes));
  std::vector<std::vector<std::vector<float>>> scores(images.size(), std::vector<std::vector<float>>(num_classes));
  const float* data = out.ptr<float>();
  for (int i = 0; i < rows; ++i) {
    const float* row = data + size_t(i) * cols;
    const float obj = row[4];
    if (obj < min_conf) continue;
    const float* cls = row + 5;
    const int best = int(std::max_element(cls, cls + num_classes) - cls);
    if (!wanted_[best]) continue;
    const float score = obj * cls[best];
    if (score < (best == 0 ? params_.person_confidence : params_.confidence)) continue;
    // The cell that holds the box centre says which image it belongs to.
    const int gx = std::clamp(int(std::floor((row[0] - origin.x) / cell.width)), 0, grid - 1);
    const int gy = std::clamp(int(std::floor((row[1] - origin.y) / cell.height)), 0, grid - 1);
    const size_t img = size_t(gy * grid + gx);
    if (img >= images.size()) continue;
    const Placement& pl = place[img];
    const float x = (row[0] - 0.5f * row[2] - pl.x0) / pl.r, y = (row[1] - 0.5f * row[3] - pl.y0) / pl.r;
    boxes[img][best].emplace_back(x, y, row[2] / pl.r, row[3] / pl.r);
    scores[img][best].push_back(score);
  }
  std::vector<std::vector<Detection>> result(images.size());
  for (size_t img = 0; img < images.size(); ++img) {
    auto& dets = result[img];
    const cv::Rect2f frame(0, 0, float(images[img].cols), float(images[img].rows));
    for (int c = 0; c < num_classes; ++c) {
      if (boxes[img][c].empty()) continue;
      std::vector<int> keep;
      cv::dnn::NMSBoxes(boxes[img][c], scores[img][c], 0.0f, params_.nms, keep);
      for (int k : keep) {
        Detection d;
        d.box = cv::Rect2f(boxes[img][c][k]) & frame;
        d.class_id = c;
        d.score = scores[img][c][k];
        if (d.box.area() > 0) dets.push_back(d);
      }
    }
    std::sort(dets.begin(), dets.end(), [](const Detection& a, const Detection& b) {
      if (a.score != b.score) return a.score > b.score;
      return a.box.x < b.box.x;
    });
  }
  return result;
}

}  // namespace tkgslam::dynamic
