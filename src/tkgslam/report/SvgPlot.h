#pragma once
// Minimal SVG line plots for the HTML report (no dependencies, self-contained output).
#include <string>
#include <vector>

namespace tkgslam::report {

struct Series {
  std::string name;
  std::string colour;  ///< CSS colour
  std::vector<double> x, y;
};

/// A line plot with axes, tick labels and a legend. Returns an <svg> element.
std::string svgLinePlot(const std::string& title, const std::string& x_label, const std::string& y_label,
                        const std::vector<Series>& series, int width = 560, int height = 260);

/// Horizontal bars (e.g. time per module). Returns an <svg> element.
std::string svgBarChart(const std::string& title, const std::vector<std::pair<std::string, double>>& bars,
                        const std::string& unit, int width = 560);

/// Escapes &, <, >, " for HTML/XML text.
std::string escapeXml(const std::string& text);

}  // namespace tkgslam::report
