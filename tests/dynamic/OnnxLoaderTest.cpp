#include <cmath>
#include <cstring>
#include <string>

#include <opencv2/dnn.hpp>
#include <opencv2/dnn/all_layers.hpp>
#include <opencv2/imgcodecs.hpp>

#include <gtest/gtest.h>

#include "TestSupport.h"
#include "tkgslam/dynamic/OnnxLoader.h"
#include "tkgslam/dynamic/VectorSigmoidLayer.h"

namespace tkgslam {
namespace {

// Layers of `type` that are not OpenCV's own class `Own`.
template <class Own>
int oursOfType(cv::dnn::Net& net, const std::string& type) {
  int n = 0;
  for (const auto& name : net.getLayerNames()) {
    const auto layer = net.getLayer(net.getLayerId(name));
    n += layer->type == type && !dynamic_cast<Own*>(layer.get());
  }
  return n;
}

std::vector<uchar> yoloModelBytes() {
  const std::string bytes = test::readFile(test::yoloModel());
  return std::vector<uchar>(bytes.begin(), bytes.end());
}

// A photo of ../shared/datasets/people as the 640 x 640 blob the export was made for.
cv::Mat photoBlob(const std::string& name) {
  const cv::Mat photo = cv::imread((test::sharedDir() / "datasets" / "people" / name).string());
  EXPECT_FALSE(photo.empty()) << name;
  return cv::dnn::blobFromImage(photo, 1.0 / 255.0, cv::Size(640, 640), cv::Scalar(), true, false);
}

TEST(OnnxLoader, YoloOnARealPhotoGivesOpenCvsOutputAndTheRegistryIsRestored) {
  TKGSLAM_REQUIRE_SHARED();
  const std::vector<uchar> model = yoloModelBytes();
  cv::dnn::Net ours = dynamic::readOnnxWithFastLayers(model);
  cv::dnn::Net opencv = cv::dnn::readNetFromONNX(model);  // loaded after ours: OpenCV's layers again
  EXPECT_EQ(oursOfType<cv::dnn::PermuteLayer>(ours, "Permute"), 3);   // the head's three levels
  EXPECT_EQ(oursOfType<cv::dnn::SigmoidLayer>(ours, "Sigmoid"), 3);   // the head's
  EXPECT_EQ(oursOfType<cv::dnn::SigmoidLayer>(ours, dynamic::kFusedSiluType), 57);  // SiLU, Sigmoid + Mul fused
  EXPECT_EQ(oursOfType<cv::dnn::PermuteLayer>(opencv, "Permute"), 0);
  EXPECT_EQ(oursOfType<cv::dnn::SigmoidLayer>(opencv, "Sigmoid"), 0);
  EXPECT_EQ(oursOfType<cv::dnn::SigmoidLayer>(opencv, dynamic::kFusedSiluType), 0);

  const cv::Mat blob = photoBlob("bus.jpg");
  ours.setInput(blob);
  const cv::Mat a = ours.forward().clone();
  opencv.setInput(blob);
  const cv::Mat b = opencv.forward().clone();
  ASSERT_EQ(a.total(), b.total());
  // Every output (box in input pixels, scores in 0..1) within 1e-3 of OpenCV's; the persons the same.
  int persons = 0, persons_opencv = 0;
  double worst = 0;
  for (int i = 0; i < a.size[1]; ++i) {
    const float* p = a.ptr<float>(0, i);
    const float* q = b.ptr<float>(0, i);
    for (int k = 0; k < a.size[2]; ++k) worst = std::max(worst, double(std::abs(p[k] - q[k])));
    persons += p[4] * p[5] > 0.5f;
    persons_opencv += q[4] * q[5] > 0.5f;
  }
  EXPECT_LT(worst, 1e-3);
  EXPECT_GT(persons, 3);
  EXPECT_EQ(persons, persons_opencv);
}

TEST(OnnxLoader, FusingSiluChangesNoBitOfYolosOutput) {
  TKGSLAM_REQUIRE_SHARED();
  const std::vector<uchar> model = yoloModelBytes();
  cv::dnn::Net fused = dynamic::readOnnxWithFastLayers(model);
  // The same model with our Sigmoid layer, its Sigmoid + Mul pairs left as they are.
  cv::dnn::LayerFactory::registerLayer("Sigmoid", dynamic::createVectorSigmoidLayer);
  cv::dnn::Net pairs = cv::dnn::readNetFromONNX(model);
  for (const auto& name : pairs.getLayerNames()) pairs.getLayer(pairs.getLayerId(name));
  cv::dnn::LayerFactory::unregisterLayer("Sigmoid");
  EXPECT_EQ(oursOfType<cv::dnn::SigmoidLayer>(pairs, "Sigmoid"), 60);

  const cv::Mat blob = photoBlob("zidane.jpg");
  fused.setInput(blob);
  const cv::Mat a = fused.forward().clone();
  pairs.setInput(blob);
  const cv::Mat b = pairs.forward().clone();
  ASSERT_EQ(a.total(), b.total());
  EXPECT_EQ(std::memcmp(a.data, b.data, a.total() * a.elemSize()), 0);
}

}  // namespace
}  // namespace tkgslam
