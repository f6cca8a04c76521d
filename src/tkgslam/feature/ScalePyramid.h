#pragma once
// Scale factors of the ORB pyramid, shared by matching and optimisation.
#include <cmath>
#include <vector>

namespace tkgslam::feature {

struct ScalePyramid {
  int levels = 8;
  double scale_factor = 1.2;
  double log_scale_factor = std::log(1.2);
  std::vector<double> scales;      ///< scale_factor^level
  std::vector<double> inv_scales;
  std::vector<double> sigma2;      ///< scales^2: keypoint position variance grows with level
  std::vector<double> inv_sigma2;

  static ScalePyramid make(int levels, double scale_factor) {
    ScalePyramid p;
    p.levels = levels;
    p.scale_factor = scale_factor;
    p.log_scale_factor = std::log(scale_factor);
    for (int l = 0; l < levels; ++l) {
      const double s = std::pow(scale_factor, l);
      p.scales.push_back(s);
      p.inv_scales.push_back(1.0 / s);
      p.sigma2.push_back(s * s);
      p.inv_sigma2.push_back(1.0 / (s * s));
    }
    return p;
  }
};

}  // namespace tkgslam::feature
