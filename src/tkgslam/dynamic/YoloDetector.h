#pragma once
// YOLOv5 object detector on OpenCV DNN. Loads any YOLOv5 ONNX export with the standard I/O:
// input 1x3xSxS RGB in [0, 1], letterboxed with grey (114); output 1xNx(5+C) rows of
// cx, cy, w, h (input pixels), objectness, C class scores (already sigmoid-ed).
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
  std::string model;          ///< path to the ONNX file
  int input_size = 640;       ///< S (multiple of 32)
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

 private:
  DetectorParams params_;
  cv::dnn::Net net_;
  std::vector<char> wanted_;  ///< per class id
  std::mutex mutex_;
};

}  // namespace tkgslam::dynamic
