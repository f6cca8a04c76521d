#include "tkgslam/dynamic/ElementwiseLayer.h"

#include <algorithm>
#include <vector>

namespace tkgslam::dynamic {

void forwardElementwise(cv::InputArrayOfArrays inputs_arr, cv::OutputArrayOfArrays outputs_arr,
                        void (*function)(const float* x, float* y, size_t n)) {
  std::vector<cv::Mat> inputs, outputs;
  inputs_arr.getMatVector(inputs);
  outputs_arr.getMatVector(outputs);
  CV_Assert(inputs.size() == outputs.size());
  for (size_t i = 0; i < inputs.size(); ++i) {
    CV_Assert(inputs[i].type() == CV_32F && inputs[i].isContinuous() && outputs[i].isContinuous() &&
              outputs[i].total() == inputs[i].total());
    const float* x = inputs[i].ptr<float>();
    float* y = outputs[i].ptr<float>();
    const size_t n = inputs[i].total();
    constexpr size_t kStripe = 1 << 15;  // values per task
    cv::parallel_for_(cv::Range(0, int((n + kStripe - 1) / kStripe)), [&](const cv::Range& range) {
      const size_t begin = size_t(range.start) * kStripe, end = std::min(n, size_t(range.end) * kStripe);
      function(x + begin, y + begin, end - begin);
    });
  }
}

}  // namespace tkgslam::dynamic
