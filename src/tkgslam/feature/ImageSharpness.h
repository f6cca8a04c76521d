#pragma once
// A cheap motion-blur measure of a grey image, for telling blurred frames from sharp ones of the
// same scene (the value depends on scene content, so only ratios between nearby frames mean
// anything).
#include <opencv2/core.hpp>

namespace tkgslam::feature {

/// Mean squared image gradient of the half-resolution image along the weakest of four directions
/// (0, 45, 90, 135 degrees), in grey levels squared. Motion blur smears along one direction and
/// corners need gradients in two, so the weakest direction is what tells: a 31 px smear lowers it
/// 6-9 times, where an isotropic measure (Laplacian variance) can miss a smear along the scene's
/// dominant edges. Throws InputError unless `gray` is 8-bit, 1 channel.
double imageSharpness(const cv::Mat& gray);

}  // namespace tkgslam::feature
