#pragma once
// A YOLOv5 ONNX export bakes its export size into the detection head: the Reshape targets
// (1 x anchors x (5+C) x gh x gw and 1 x anchors*gh*gw x (5+C)), the cell-offset grid added to the
// box centres and the anchor sizes repeated over every cell. OpenCV DNN then refuses any other
// input size, although the convolutions before the head would run at any size. Rewriting those
// few layers lets the detector run on an input of the image's own aspect ratio (640 x 480 instead of
// a letterboxed 640 x 640: a quarter less work for the same boxes) or at a lower resolution.
#include <opencv2/core.hpp>
#include <opencv2/dnn.hpp>

namespace tkgslam::dynamic {

/// The square input size (pixels) the net's YOLOv5 head was exported for (8 x its finest grid),
/// or 0 when the head is not the one recognised: three levels at strides 8, 16 and 32, each with a
/// grid of cell offsets (x - 0.5, y - 0.5), anchor sizes repeated over its cells and one reshape to
/// 1 x anchors x (5+C) x cells x cells.
int yoloHeadExportSize(cv::dnn::Net& net);

/// Rewrites a recognised head for an input of `input` pixels (width and height multiples of 32).
/// Use on a freshly loaded net: OpenCV fuses layers on the first forward pass. Returns false and
/// leaves the net unchanged when the head is not recognised or the size is not a multiple of 32.
bool resizeYoloHead(cv::dnn::Net& net, cv::Size input);

}  // namespace tkgslam::dynamic
