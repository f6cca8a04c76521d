#pragma once
// Binary-free ASCII PLY of a coloured point cloud (MeshLab, CloudCompare, Open3D read it).
#include <string>
#include <vector>

#include <opencv2/core.hpp>

#include "tkgslam/common/Pose.h"

namespace tkgslam::io {

struct ColouredPoint {
  Vec3 position;       ///< world frame, metres
  cv::Vec3b bgr{128, 128, 128};
};

/// Throws InputError if the file cannot be written.
void writePly(const std::string& path, const std::vector<ColouredPoint>& points);

}  // namespace tkgslam::io
