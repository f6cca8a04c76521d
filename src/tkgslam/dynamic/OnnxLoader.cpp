#include "tkgslam/dynamic/OnnxLoader.h"

#include <mutex>
#include <string>
#include <utility>

#include <opencv2/dnn/layer.hpp>

#include "tkgslam/dynamic/OnnxSiluFusion.h"
#include "tkgslam/dynamic/TransposingPermuteLayer.h"
#include "tkgslam/dynamic/VectorSigmoidLayer.h"
#include "tkgslam/dynamic/VectorSiluLayer.h"

namespace tkgslam::dynamic {

namespace {

/// Our constructor for one layer type while it lives; OpenCV's again after.
class ScopedLayerRegistration {
 public:
  ScopedLayerRegistration(std::string type, cv::dnn::LayerFactory::Constructor constructor) : type_(std::move(type)) {
    cv::dnn::LayerFactory::registerLayer(type_, constructor);
  }
  ~ScopedLayerRegistration() { cv::dnn::LayerFactory::unregisterLayer(type_); }
  ScopedLayerRegistration(const ScopedLayerRegistration&) = delete;
  ScopedLayerRegistration& operator=(const ScopedLayerRegistration&) = delete;

 private:
  std::string type_;
};

}  // namespace

const char* const kFusedSiluType = "TkgslamSiLU";

cv::dnn::Net readOnnxWithFastLayers(const std::vector<uchar>& model) {
  const SiluFusion fused = fuseSiluNodes(model, kFusedSiluType);
  // One load at a time here keeps each register / unregister pair whole.
  static std::mutex registry;
  std::lock_guard<std::mutex> lock(registry);
  const ScopedLayerRegistration permute("Permute", createTransposingPermuteLayer);
  const ScopedLayerRegistration sigmoid("Sigmoid", createVectorSigmoidLayer);
  const ScopedLayerRegistration silu(kFusedSiluType, createVectorSiluLayer);
  cv::dnn::Net net = cv::dnn::readNetFromONNX(fused.model);
  // OpenCV creates a layer on first use; create them all while the registrations hold.
  for (const std::string& name : net.getLayerNames()) net.getLayer(net.getLayerId(name));
  return net;
}

}  // namespace tkgslam::dynamic
