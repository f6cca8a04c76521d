#pragma once
// Pose of one frame from its matches to 3-D map points: EPnP + RANSAC for a first pose without a
// prior (relocalisation, re-anchoring, loop detection), and the pose-only optimisation on the
// frame's matches. Shared by tracking and loop closing.
#include <memory>
#include <vector>

#include "tkgslam/camera/PinholeCamera.h"
#include "tkgslam/data/Frame.h"
#include "tkgslam/feature/ScalePyramid.h"
#include "tkgslam/optimize/PoseOptimizer.h"

namespace tkgslam::optimize {

/// EPnP + RANSAC from the 3-D points in `matches` (per keypoint of `frame`, may be null; world
/// frame, metres) to the frame's ideal keypoints. On success sets T_cw (world -> camera) and
/// keeps only the RANSAC inliers in `matches`. Returns the inlier count (0 on failure).
int solvePnpRansac(const data::Frame& frame, const camera::PinholeCamera& camera,
                   std::vector<std::shared_ptr<data::MapPoint>>& matches, Pose& T_cw);

/// Pose-only optimisation of frame.T_cw on the frame's current matches (frame.map_points);
/// sets frame.outlier. Returns the inliers.
int optimizeFramePose(data::Frame& frame, const PinholeIntrinsics& K, const feature::ScalePyramid& pyramid);

}  // namespace tkgslam::optimize
