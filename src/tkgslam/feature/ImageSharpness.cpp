#include "tkgslam/feature/ImageSharpness.h"

#include <algorithm>

#include <opencv2/imgproc.hpp>

#include "tkgslam/common/Error.h"

namespace tkgslam::feature {

double imageSharpness(const cv::Mat& gray) {
  if (gray.empty() || gray.type() != CV_8UC1) throw InputError("image sharpness needs an 8-bit grey image");
  // Half resolution: sensor noise and JPEG blocks weigh less, and it costs a quarter.
  cv::Mat half, dx, dy;
  cv::pyrDown(gray, half);
  cv::Sobel(half, dx, CV_32F, 1, 0);
  cv::Sobel(half, dy, CV_32F, 0, 1);
  const cv::Mat diag = dx + dy, anti = dx - dy;  // derivatives along the diagonals, times sqrt(2)
  const double energy[4] = {cv::mean(dx.mul(dx))[0], cv::mean(dy.mul(dy))[0], 0.5 * cv::mean(diag.mul(diag))[0],
                            0.5 * cv::mean(anti.mul(anti))[0]};
  return *std::min_element(energy, energy + 4);
}

}  // namespace tkgslam::feature
