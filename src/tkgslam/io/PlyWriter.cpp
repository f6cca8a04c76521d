#include "tkgslam/io/PlyWriter.h"

#include <fstream>

#include <fmt/format.h>

#include "tkgslam/common/Error.h"

namespace tkgslam::io {

void writePly(const std::string& path, const std::vector<ColouredPoint>& points) {
  std::ofstream out(path);
  if (!out) throw InputError(fmt::format("cannot write PLY file '{}'", path));
  out << "ply\nformat ascii 1.0\ncomment tkgslam sparse static map (world frame, metres)\n"
      << "element vertex " << points.size() << "\n"
      << "property float x\nproperty float y\nproperty float z\n"
      << "property uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n";
  for (const auto& p : points) {
    out << fmt::format("{:.5f} {:.5f} {:.5f} {} {} {}\n", p.position.x(), p.position.y(), p.position.z(),
                       int(p.bgr[2]), int(p.bgr[1]), int(p.bgr[0]));
  }
  if (!out) throw InputError(fmt::format("failed while writing PLY file '{}'", path));
}

}  // namespace tkgslam::io
