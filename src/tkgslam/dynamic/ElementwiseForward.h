#pragma once
// The forward pass our element-wise layers (VectorSigmoidLayer, VectorSiluLayer) share.
#include <cstddef>

#include <opencv2/core.hpp>

namespace tkgslam::dynamic {

/// Runs `function`(x, y, n) over each input blob into the output blob of the same index (CV_32F,
/// contiguous, the same number of values; may be the same memory), in tasks of 2^15 values on
/// OpenCV's threads. `function` must give each value independently of where a task starts.
void forwardElementwise(cv::InputArrayOfArrays inputs, cv::OutputArrayOfArrays outputs,
                        void (*function)(const float* x, float* y, size_t n));

}  // namespace tkgslam::dynamic
