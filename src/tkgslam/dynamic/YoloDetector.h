#pragma once
// YOLOv5 object detector on OpenCV DNN. Loads any YOLOv5 ONNX export with the standard I/O:
// input 1x3xHxW RGB in [0, 1], letterboxed with grey (114); output 1xNx(5+C) rows of
// cx, cy, w, h (input pixels), objectness, C class scores (already sigmoid-ed). The input is
// the image's aspect ratio when the export's head can be resized (resizeYoloHead), else the
// export's square.
// Only the classes of the configured dynamic set are returned; NMS is per class.
#include <mutex>
#include <string>
#include <vector>

#include <opencv2/dnn.hpp>

#include "tkgslam/dynamic/Detection.h"

namespace tkgslam::dynamic {

/// COCO ids of the paper's a-priori dynamic classes: person, animals, vehicles.
std::vector<int> defaultDynamicClasses();

struct DetectorParams {
  /// Largest input side accepted: 3.2 x the 640 the model was trained at. Larger inputs find
  /// nothing more and only cost time and memory (4096: 29 s and 2.4 GB per image; 16384 exhausts
  /// 24 GB).
  static constexpr int kMaxInputSize = 2048;
  /// An input side the network takes: a multiple of 32 (its coarsest stride) from 64 to kMaxInputSize.
  static constexpr bool validInputSize(int s) { return s >= 64 && s <= kMaxInputSize && s % 32 == 0; }

  std::string model;          ///< path to the ONNX file
  int input_size = 640;       ///< S: the input's long side, pixels (multiple of 32, 64 to kMaxInputSize)
  /// A second pass at this long side (0 = none; e.g. 320), for people near the camera: its boxes at
  /// least half the image tall join the first pass's before NMS. At 640 YOLOv5n loses many people
  /// taller than the frame (blurred, bent or seated ones of the TUM fr3 frames), which it finds
  /// at 320; it costs a second forward pass (+13 ms at 320 x 256).
  int extra_input_size = 0;
  /// Fit the input to the image's aspect ratio (S x S*h/w rounded up to 32: 640 x 480 for a VGA
  /// frame, a quarter less work than the letterboxed S x S square and the same boxes) when the
  /// model's head can be resized; otherwise, and when false, letterbox into S x S.
  bool fit_input = true;
  float confidence = 0.25f;   ///< score threshold
  float person_confidence = 0.1f;  ///< lower: missing a person costs more than a false box
  float nms = 0.45f;          ///< IoU threshold of non-maximum suppression
  std::vector<int> classes = defaultDynamicClasses();
};

class YoloDetector {
 public:
  /// Throws InputError if the model is missing, unreadable, or has an unexpected output shape.
  explicit YoloDetector(const DetectorParams& params);

  /// Detects dynamic objects in a BGR image. Serialised internally (one forward pass at a time).
  std::vector<Detection> detect(const cv::Mat& bgr);
  /// Detects in several images with one forward pass: the images are tiled into a square grid
  /// (2 x 2 for 2-4 images; each at 1/grid of the input size), so each is seen at a lower
  /// resolution for the price of one. Boxes are assigned to the image whose tile holds their
  /// centre; one result per image, in its own pixels. One image: the same as detect().
  std::vector<std::vector<Detection>> detectTiles(const std::vector<cv::Mat>& images);

  const DetectorParams& params() const { return params_; }
  /// The network input (pixels) of the last detection's first pass (before the first: S x S).
  cv::Size inputSize();

 private:
  /// One forward pass per detection: a net and the input it is prepared for.
  struct Pass {
    int size = 0;  ///< the input's long side
    cv::dnn::Net net;
    cv::Size input;
  };

  cv::dnn::Net load() const;
  /// Makes the pass's net run at `input` (reloading and resizing its head when it changes). Under mutex_.
  void prepareNet(Pass& pass, cv::Size input);

  DetectorParams params_;
  std::vector<uchar> model_bytes_;
  int export_size_ = 0;  ///< the head's export size; 0 = not resizable (runs at S x S only)
  std::vector<Pass> passes_;  ///< input_size, then extra_input_size if set
  std::vector<char> wanted_;  ///< per class id
  std::mutex mutex_;
};

}  // namespace tkgslam::dynamic
