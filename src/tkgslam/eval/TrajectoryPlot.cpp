#include "tkgslam/eval/TrajectoryPlot.h"

#include <algorithm>

#include <fmt/format.h>

#include "tkgslam/io/OutputFile.h"

namespace tkgslam::eval {

namespace {
// Blue (low error) -> red (high error).
std::string errorColour(double e, double max_e) {
  const double a = max_e > 0 ? std::clamp(e / max_e, 0.0, 1.0) : 0.0;
  const int r = int(40 + 215 * a), g = int(90 + 60 * (1 - std::abs(2 * a - 1))), b = int(255 * (1 - a));
  return fmt::format("rgb({},{},{})", r, g, b);
}
}  // namespace

std::string renderTrajectorySvg(const AteResult& ate, const std::string& title, int ah, int av) {
  static const char* kAxis = "xyz";
  const int W = 720, H = 620, M = 60;
  double min_x = 1e300, max_x = -1e300, min_y = 1e300, max_y = -1e300;
  for (const auto* pts : {&ate.gt_positions, &ate.est_aligned}) {
    for (const auto& p : *pts) {
      min_x = std::min(min_x, p[ah]);
      max_x = std::max(max_x, p[ah]);
      min_y = std::min(min_y, p[av]);
      max_y = std::max(max_y, p[av]);
    }
  }
  const double span = std::max({max_x - min_x, max_y - min_y, 1e-6});
  const double scale = (std::min(W, H - 40) - 2 * M) / span;
  auto X = [&](double x) { return M + (x - min_x) * scale; };
  auto Y = [&](double y) { return H - M - (y - min_y) * scale; };  // y up

  std::string svg = fmt::format(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{}\" height=\"{}\" viewBox=\"0 0 {} {}\">\n"
      "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
      "<text x=\"{}\" y=\"24\" font-family=\"sans-serif\" font-size=\"16\">{}</text>\n"
      "<text x=\"{}\" y=\"44\" font-family=\"sans-serif\" font-size=\"12\">ATE RMSE {:.4f} m over {} "
      "poses; {} right, {} up; scale bar {:.3f} m</text>\n",
      W, H, W, H, M, title, M, ate.stats.rmse, ate.stats.count, kAxis[ah], kAxis[av], span / 4);
  svg += fmt::format("<line x1=\"{}\" y1=\"{}\" x2=\"{:.1f}\" y2=\"{}\" stroke=\"black\" stroke-width=\"2\"/>\n",
                     M, H - 20, M + span / 4 * scale, H - 20);
  std::string gt_path;
  for (size_t i = 0; i < ate.gt_positions.size(); ++i) {
    gt_path += fmt::format("{}{:.2f},{:.2f} ", i ? "L" : "M", X(ate.gt_positions[i][ah]), Y(ate.gt_positions[i][av]));
  }
  svg += fmt::format("<path d=\"{}\" fill=\"none\" stroke=\"black\" stroke-width=\"1.5\"/>\n", gt_path);
  for (size_t i = 1; i < ate.est_aligned.size(); ++i) {
    const auto& a = ate.est_aligned[i - 1];
    const auto& b = ate.est_aligned[i];
    svg += fmt::format("<line x1=\"{:.2f}\" y1=\"{:.2f}\" x2=\"{:.2f}\" y2=\"{:.2f}\" stroke=\"{}\" stroke-width=\"2\"/>\n",
                       X(a[ah]), Y(a[av]), X(b[ah]), Y(b[av]), errorColour(ate.errors[i], ate.stats.max));
  }
  svg += fmt::format(
      "<g font-family=\"sans-serif\" font-size=\"12\"><line x1=\"{}\" y1=\"60\" x2=\"{}\" y2=\"60\" stroke=\"black\" "
      "stroke-width=\"2\"/><text x=\"{}\" y=\"64\">ground truth</text>"
      "<line x1=\"{}\" y1=\"78\" x2=\"{}\" y2=\"78\" stroke=\"{}\" stroke-width=\"2\"/><text x=\"{}\" y=\"82\">estimate, "
      "error 0 m</text><line x1=\"{}\" y1=\"96\" x2=\"{}\" y2=\"96\" stroke=\"{}\" stroke-width=\"2\"/><text x=\"{}\" "
      "y=\"100\">estimate, error {:.4f} m (max)</text></g>\n</svg>\n",
      W - 230, W - 200, W - 195, W - 230, W - 200, errorColour(0, 1), W - 195, W - 230, W - 200,
      errorColour(1, 1), W - 195, ate.stats.max);
  return svg;
}

void writeTrajectorySvg(const std::string& path, const AteResult& ate, const std::string& title) {
  io::writeOutputFile(path, "plot", renderTrajectorySvg(ate, title));
}

}  // namespace tkgslam::eval
