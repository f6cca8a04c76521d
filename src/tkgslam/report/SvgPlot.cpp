#include "tkgslam/report/SvgPlot.h"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

namespace tkgslam::report {

std::string escapeXml(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      default: out += c;
    }
  }
  return out;
}

std::string svgLinePlot(const std::string& title, const std::string& x_label, const std::string& y_label,
                        const std::vector<Series>& series, int W, int H) {
  const int L = 60, R = 20, T = 30, B = 40;
  double x0 = 1e300, x1 = -1e300, y0 = 0, y1 = -1e300;
  for (const auto& s : series) {
    for (double v : s.x) x0 = std::min(x0, v), x1 = std::max(x1, v);
    for (double v : s.y) y0 = std::min(y0, v), y1 = std::max(y1, v);
  }
  if (!(x1 > x0)) x0 = 0, x1 = 1;
  if (!(y1 > y0)) y1 = y0 + 1;
  auto X = [&](double v) { return L + (v - x0) / (x1 - x0) * (W - L - R); };
  auto Y = [&](double v) { return H - B - (v - y0) / (y1 - y0) * (H - T - B); };
  std::string svg = fmt::format(
      "<svg class=\"plot\" xmlns=\"http://www.w3.org/2000/svg\" width=\"{}\" height=\"{}\" viewBox=\"0 0 {} {}\">"
      "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>"
      "<text x=\"{}\" y=\"18\" font-size=\"13\" font-family=\"sans-serif\">{}</text>"
      "<line x1=\"{}\" y1=\"{}\" x2=\"{}\" y2=\"{}\" stroke=\"#333\"/><line x1=\"{}\" y1=\"{}\" x2=\"{}\" y2=\"{}\" stroke=\"#333\"/>",
      W, H, W, H, L, escapeXml(title), L, H - B, W - R, H - B, L, T, L, H - B);
  for (int k = 0; k <= 4; ++k) {
    const double xv = x0 + (x1 - x0) * k / 4, yv = y0 + (y1 - y0) * k / 4;
    svg += fmt::format("<text x=\"{:.0f}\" y=\"{}\" font-size=\"10\" font-family=\"sans-serif\" text-anchor=\"middle\">{:.3g}</text>",
                       X(xv), H - B + 14, xv);
    svg += fmt::format("<text x=\"{}\" y=\"{:.0f}\" font-size=\"10\" font-family=\"sans-serif\" text-anchor=\"end\">{:.3g}</text>"
                       "<line x1=\"{}\" y1=\"{:.1f}\" x2=\"{}\" y2=\"{:.1f}\" stroke=\"#eee\"/>",
                       L - 4, Y(yv) + 3, yv, L + 1, Y(yv), W - R, Y(yv));
  }
  svg += fmt::format("<text x=\"{}\" y=\"{}\" font-size=\"11\" font-family=\"sans-serif\" text-anchor=\"middle\">{}</text>",
                     (L + W - R) / 2, H - 6, escapeXml(x_label));
  svg += fmt::format("<text x=\"14\" y=\"{}\" font-size=\"11\" font-family=\"sans-serif\" transform=\"rotate(-90 14 {})\" "
                     "text-anchor=\"middle\">{}</text>",
                     (T + H - B) / 2, (T + H - B) / 2, escapeXml(y_label));
  int legend = 0;
  for (const auto& s : series) {
    if (s.x.empty()) continue;
    std::string pts;
    const size_t step = std::max<size_t>(1, s.x.size() / 1500);  // keep the page light
    for (size_t i = 0; i < s.x.size(); i += step) pts += fmt::format("{:.1f},{:.1f} ", X(s.x[i]), Y(s.y[i]));
    svg += fmt::format("<polyline fill=\"none\" stroke=\"{}\" stroke-width=\"1.5\" points=\"{}\"/>", s.colour, pts);
    svg += fmt::format("<rect x=\"{}\" y=\"{}\" width=\"10\" height=\"10\" fill=\"{}\"/><text x=\"{}\" y=\"{}\" font-size=\"11\" "
                       "font-family=\"sans-serif\">{}</text>",
                       W - R - 150, T + 4 + 15 * legend, s.colour, W - R - 135, T + 13 + 15 * legend, escapeXml(s.name));
    ++legend;
  }
  return svg + "</svg>";
}

std::string svgBarChart(const std::string& title, const std::vector<std::pair<std::string, double>>& bars,
                        const std::string& unit, int W) {
  const int row = 22, L = 170, T = 28;
  const int H = T + row * int(bars.size()) + 10;
  double mx = 0;
  for (const auto& b : bars) mx = std::max(mx, b.second);
  if (mx <= 0) mx = 1;
  std::string svg = fmt::format(
      "<svg class=\"plot\" xmlns=\"http://www.w3.org/2000/svg\" width=\"{}\" height=\"{}\"><rect width=\"100%\" height=\"100%\" "
      "fill=\"white\"/><text x=\"8\" y=\"18\" font-size=\"13\" font-family=\"sans-serif\">{}</text>",
      W, H, escapeXml(title));
  for (size_t i = 0; i < bars.size(); ++i) {
    const double w = bars[i].second / mx * (W - L - 90);
    const int y = T + row * int(i);
    svg += fmt::format("<text x=\"{}\" y=\"{}\" font-size=\"11\" font-family=\"sans-serif\" text-anchor=\"end\">{}</text>"
                       "<rect x=\"{}\" y=\"{}\" width=\"{:.1f}\" height=\"14\" fill=\"#4a7fb5\"/>"
                       "<text x=\"{:.1f}\" y=\"{}\" font-size=\"11\" font-family=\"sans-serif\">{:.2f} {}</text>",
                       L - 6, y + 11, escapeXml(bars[i].first), L, y, w, L + w + 4, y + 11, bars[i].second, unit);
  }
  return svg + "</svg>";
}

}  // namespace tkgslam::report
