#include "tkgslam/dynamic/YoloDetector.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <iterator>

#include <fmt/format.h>
#include <opencv2/imgproc.hpp>

#include "tkgslam/common/Error.h"
#include "tkgslam/dynamic/OnnxLoader.h"
#include "tkgslam/dynamic/YoloHeadResize.h"
#include "tkgslam/io/InputFile.h"

namespace tkgslam::dynamic {

namespace {

/// The extra pass (DetectorParams::extra_input_size) is for people near the camera: of its boxes only
/// those at least this share of the image's height count. Smaller people the first pass finds
/// better, and the extra pass's small boxes are looser and some false (with them, `TKG` on the first
/// 300 frames of fr1_xyz: 0.0112 m ATE against 0.0108; detector_input_300.md, session 59).
constexpr double kExtraPassMinHeight = 0.5;

/// Where one image sits in the network input: scale and top-left corner (input pixels).
struct Placement {
  float r;
  int x0, y0;
};

/// The network input: grid x grid cells of `cell` pixels from `origin`, each holding one image
/// letterboxed (grey 114 around, as YOLOv5 trains).
struct TiledInput {
  int grid = 1;
  cv::Size cell;
  cv::Point origin;
  cv::Mat input;
  std::vector<Placement> place;  ///< per image
};

/// The images fill a grid x grid block of equal cells: square cells in an S x S input, or with
/// `fit`, cells of the images' aspect ratio (S / grid on the long side), the input rounded up to
/// multiples of 32.
TiledInput tileImages(const std::vector<cv::Mat>& images, int S, bool fit) {
  TiledInput t;
  t.grid = int(std::ceil(std::sqrt(double(images.size()) - 1e-9)));
  const int grid = t.grid;
  t.cell = cv::Size(S / grid, S / grid);
  cv::Size input_size(S, S);
  if (fit) {
    t.cell = cv::Size(0, 0);
    for (const auto& bgr : images) {
      const double r = double(S) / grid / std::max(bgr.cols, bgr.rows);
      t.cell.width = std::max({t.cell.width, 1, int(std::lround(bgr.cols * r))});
      t.cell.height = std::max({t.cell.height, 1, int(std::lround(bgr.rows * r))});
    }
    const auto roundUp = [](int v) { return (v + 31) / 32 * 32; };
    input_size = cv::Size(roundUp(grid * t.cell.width), roundUp(grid * t.cell.height));
  }
  t.origin = cv::Point((input_size.width - grid * t.cell.width) / 2, (input_size.height - grid * t.cell.height) / 2);
  t.input = cv::Mat(input_size, CV_8UC3, cv::Scalar(114, 114, 114));
  for (size_t i = 0; i < images.size(); ++i) {
    const cv::Mat& bgr = images[i];
    const float r = std::min(float(t.cell.width) / bgr.cols, float(t.cell.height) / bgr.rows);
    const int nw = std::max(1, int(std::lround(bgr.cols * r))), nh = std::max(1, int(std::lround(bgr.rows * r)));
    const int cx = t.origin.x + int(i % grid) * t.cell.width, cy = t.origin.y + int(i / grid) * t.cell.height;
    const Placement pl{r, cx + (t.cell.width - nw) / 2, cy + (t.cell.height - nh) / 2};
    cv::resize(bgr, t.input(cv::Rect(pl.x0, pl.y0, nw, nh)), cv::Size(nw, nh), 0, 0, cv::INTER_LINEAR);
    t.place.push_back(pl);
  }
  return t;
}

/// One image's candidate boxes (image pixels) and scores, per class id.
struct ClassCandidates {
  std::vector<std::vector<cv::Rect2d>> boxes;
  std::vector<std::vector<float>> scores;
};

/// The network's rows (cx, cy, w, h, objectness, class scores; input pixels) above the score
/// thresholds, of the wanted classes, given to the image whose cell holds the box centre.
std::vector<ClassCandidates> decodeRows(const cv::Mat& out, const TiledInput& t, const DetectorParams& p,
                                        const std::vector<char>& wanted) {
  const int rows = out.size[1], cols = out.size[2];
  const int num_classes = cols - 5;
  const float min_conf = std::min(p.confidence, p.person_confidence);
  std::vector<ClassCandidates> per_image(t.place.size(), {std::vector<std::vector<cv::Rect2d>>(num_classes),
                                                          std::vector<std::vector<float>>(num_classes)});
  const float* data = out.ptr<float>();
  for (int i = 0; i < rows; ++i) {
    const float* row = data + size_t(i) * cols;
    const float obj = row[4];
    if (obj < min_conf) continue;
    const float* cls = row + 5;
    const int best = int(std::max_element(cls, cls + num_classes) - cls);
    if (!wanted[best]) continue;
    const float score = obj * cls[best];
    if (score < (best == 0 ? p.person_confidence : p.confidence)) continue;
    const int gx = std::clamp(int(std::floor((row[0] - t.origin.x) / t.cell.width)), 0, t.grid - 1);
    const int gy = std::clamp(int(std::floor((row[1] - t.origin.y) / t.cell.height)), 0, t.grid - 1);
    const size_t img = size_t(gy * t.grid + gx);
    if (img >= t.place.size()) continue;
    const Placement& pl = t.place[img];
    const float x = (row[0] - 0.5f * row[2] - pl.x0) / pl.r, y = (row[1] - 0.5f * row[3] - pl.y0) / pl.r;
    per_image[img].boxes[best].emplace_back(x, y, row[2] / pl.r, row[3] / pl.r);
    per_image[img].scores[best].push_back(score);
  }
  return per_image;
}

/// Non-maximum suppression per class, boxes clipped to the image; best score first (ties: left first).
std::vector<Detection> suppress(const ClassCandidates& c, cv::Size image, float nms) {
  std::vector<Detection> dets;
  const cv::Rect2f frame(0, 0, float(image.width), float(image.height));
  for (size_t id = 0; id < c.boxes.size(); ++id) {
    if (c.boxes[id].empty()) continue;
    std::vector<int> keep;
    cv::dnn::NMSBoxes(c.boxes[id], c.scores[id], 0.0f, nms, keep);
    for (int k : keep) {
      Detection d;
      d.box = cv::Rect2f(c.boxes[id][k]) & frame;
      d.class_id = int(id);
      d.score = c.scores[id][k];
      if (d.box.area() > 0) dets.push_back(d);
    }
  }
  std::sort(dets.begin(), dets.end(), [](const Detection& a, const Detection& b) {
    if (a.score != b.score) return a.score > b.score;
    return a.box.x < b.box.x;
  });
  return dets;
}

/// Appends `from`'s candidates at least `min_height` tall (image pixels) to `into`, class by class.
void appendTallCandidates(const ClassCandidates& from, double min_height, ClassCandidates& into) {
  for (size_t id = 0; id < from.boxes.size(); ++id) {
    for (size_t k = 0; k < from.boxes[id].size(); ++k) {
      if (from.boxes[id][k].height < min_height) continue;
      into.boxes[id].push_back(from.boxes[id][k]);
      into.scores[id].push_back(from.scores[id][k]);
    }
  }
}

}  // namespace

std::vector<int> defaultDynamicClasses() {
  // person; bicycle car motorcycle airplane bus train truck boat; bird cat dog horse sheep cow
  // elephant bear zebra giraffe.
  return {0, 1, 2, 3, 4, 5, 6, 7, 8, 14, 15, 16, 17, 18, 19, 20, 21, 22, 23};
}

YoloDetector::YoloDetector(const DetectorParams& params) : params_(params) {
  if (params_.model.empty()) throw InputError("detector: no model path configured (dynamic.model)");
  std::ifstream file = io::openInputFile(params_.model, "detector: model file", std::ios::binary);
  const auto checkSize = [](int size) {
    if (!DetectorParams::validInputSize(size)) {
      throw InputError(fmt::format("detector: input size {} must be a multiple of 32 from 64 to {}", size,
                                   DetectorParams::kMaxInputSize));
    }
  };
  checkSize(params_.input_size);
  if (params_.extra_input_size != 0) checkSize(params_.extra_input_size);
  if (!(params_.confidence > 0 && params_.confidence < 1) || !(params_.person_confidence > 0 && params_.person_confidence < 1) ||
      !(params_.nms > 0 && params_.nms <= 1)) {
    throw InputError("detector: confidence thresholds must be in (0, 1) and nms in (0, 1]");
  }
  model_bytes_.assign(std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>());
  if (model_bytes_.empty()) throw InputError(fmt::format("detector: ONNX model '{}' is empty", params_.model));
  cv::Mat out;
  try {
    passes_.push_back({params_.input_size, load(), {}});
    if (params_.extra_input_size > 0) passes_.push_back({params_.extra_input_size, load(), {}});
    export_size_ = yoloHeadExportSize(passes_.front().net);
    // Probe the output shape once so a wrong model fails at start-up, not mid-run.
    for (Pass& pass : passes_) {
      prepareNet(pass, cv::Size(pass.size, pass.size));
      cv::Mat probe(pass.size, pass.size, CV_8UC3, cv::Scalar(114, 114, 114));
      pass.net.setInput(cv::dnn::blobFromImage(probe, 1.0 / 255.0, cv::Size(), cv::Scalar(), true, false));
      out = pass.net.forward();
    }
  } catch (const cv::Exception& e) {
    std::string why = e.what();
    while (!why.empty() && std::isspace(static_cast<unsigned char>(why.back()))) why.pop_back();
    throw InputError(fmt::format("detector: model '{}' does not load or run at input size {}: {}", params_.model,
                                 params_.input_size, why));
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
  cv::dnn::Net net = readOnnxWithFastLayers(model_bytes_);
  if (net.empty()) throw InputError(fmt::format("detector: ONNX model '{}' is empty", params_.model));
  net.setPreferableBackend(cv::dnn::DNN_BACKEND_OPENCV);
  net.setPreferableTarget(cv::dnn::DNN_TARGET_CPU);
  return net;
}

void YoloDetector::prepareNet(Pass& pass, cv::Size input) {
  if (input == pass.input) return;
  if (!pass.input.empty()) pass.net = load();  // a net that ran at another size has fused its layers
  if (export_size_ > 0 && input != cv::Size(export_size_, export_size_) && !resizeYoloHead(pass.net, input)) {
    throw InputError(fmt::format("detector: cannot resize the head of '{}' to {} x {}", params_.model, input.width,
                                 input.height));
  }
  pass.input = input;
}

cv::Size YoloDetector::inputSize() {
  std::lock_guard<std::mutex> lock(mutex_);
  return passes_.front().input;
}

std::vector<Detection> YoloDetector::detect(const cv::Mat& bgr) { return detectTiles({bgr}).front(); }

std::vector<std::vector<Detection>> YoloDetector::detectTiles(const std::vector<cv::Mat>& images) {
  if (images.empty()) return {};
  for (const auto& bgr : images) {
    if (bgr.empty() || bgr.type() != CV_8UC3) throw InputError("detector: expects 8-bit BGR images");
  }
  const auto runPass = [&](Pass& pass) {
    const TiledInput tiled = tileImages(images, pass.size, params_.fit_input && export_size_ > 0);
    cv::Mat out;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      prepareNet(pass, tiled.input.size());
      pass.net.setInput(cv::dnn::blobFromImage(tiled.input, 1.0 / 255.0, cv::Size(), cv::Scalar(), true, false));
      out = pass.net.forward();
    }
    return decodeRows(out, tiled, params_, wanted_);
  };
  // The extra pass's tall boxes join the first pass's, and all go through one NMS.
  std::vector<ClassCandidates> candidates = runPass(passes_.front());
  for (size_t i = 1; i < passes_.size(); ++i) {
    const std::vector<ClassCandidates> extra = runPass(passes_[i]);
    for (size_t img = 0; img < images.size(); ++img) {
      appendTallCandidates(extra[img], kExtraPassMinHeight * images[img].rows, candidates[img]);
    }
  }
  std::vector<std::vector<Detection>> result(images.size());
  for (size_t img = 0; img < images.size(); ++img) {
    result[img] = suppress(candidates[img], images[img].size(), params_.nms);
  }
  return result;
}

}  // namespace tkgslam::dynamic
