#include "tkgslam/io/PlyWriter.h"

#include <fmt/format.h>

#include "tkgslam/io/OutputFile.h"

namespace tkgslam::io {

void writePly(const std::string& path, const std::vector<ColouredPoint>& points) {
  std::string text = fmt::format(
      "ply\nformat ascii 1.0\ncomment tkgslam sparse static map (world frame, metres)\nelement vertex {}\n"
      "property float x\nproperty float y\nproperty float z\n"
      "property uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n",
      points.size());
  for (const auto& p : points) {
    text += fmt::format("{:.5f} {:.5f} {:.5f} {} {} {}\n", p.position.x(), p.position.y(), p.position.z(),
                        int(p.bgr[2]), int(p.bgr[1]), int(p.bgr[0]));
  }
  writeOutputFile(path, "PLY file", text);
}

}  // namespace tkgslam::io
