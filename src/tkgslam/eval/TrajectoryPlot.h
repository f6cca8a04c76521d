#pragma once
// SVG plot of an ATE result: top view (x-y plane of the ground-truth frame) of the ground truth
// and the aligned estimate, the estimate coloured by its position error.
#include <string>

#include "tkgslam/eval/Ate.h"

namespace tkgslam::eval {

/// Returns a standalone SVG document. `axis_h` / `axis_v`: coordinates (0 = x, 1 = y, 2 = z) on the
/// horizontal / vertical axis; the default is the top view.
std::string renderTrajectorySvg(const AteResult& ate, const std::string& title, int axis_h = 0, int axis_v = 1);

/// Writes the SVG to `path`; throws InputError if it cannot be written.
void writeTrajectorySvg(const std::string& path, const AteResult& ate, const std::string& title);

}  // namespace tkgslam::eval
