#include "tkgslam/report/HtmlReport.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>

#include <fmt/format.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <yaml-cpp/yaml.h>

#include "tkgslam/common/Error.h"
#include "tkgslam/eval/Ate.h"
#include "tkgslam/eval/Rpe.h"
#include "tkgslam/eval/TrajectoryPlot.h"
#include "tkgslam/io/OutputFile.h"
#include "tkgslam/io/TrajectoryFile.h"
#include "tkgslam/io/TextParsing.h"
#include "tkgslam/io/TumDataset.h"
#include "tkgslam/report/SvgPlot.h"
#include "tkgslam/report/ViewerScript.h"

namespace fs = std::filesystem;

namespace tkgslam::report {

namespace {

std::string slurp(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

/// One JSON document written by `tkgslam run`. JSON is YAML (1.2), so yaml-cpp reads it, escapes
/// included: a dataset path with a quote or a backslash comes back as written. `where` names the file
/// (and line) in the error.
YAML::Node parseJson(const std::string& text, const std::string& where) {
  try {
    return YAML::Load(text);
  } catch (const YAML::Exception& e) {
    throw InputError(fmt::format("{}: not valid JSON ({})", where, e.msg));
  }
}

/// The text of `key` in a JSON object: a string unescaped, a number or true/false as written; ""
/// where the key is missing or null, or `object` is not an object.
std::string scalarText(const YAML::Node& object, const char* key) {
  if (!object.IsMap()) return "";
  const YAML::Node value = object[key];
  return value.IsDefined() && value.IsScalar() ? value.Scalar() : "";
}

/// Finds the number under one key in a line of dynamic.jsonl. Those lines hold numbers and
/// true/false only, and up to thousands of keypoints each: parsed whole by yaml-cpp, a 300-frame
/// run's report took 1.1 s instead of 0.33 s. Compiled once per key, not per line.
struct JsonNumberKey {
  explicit JsonNumberKey(const char* k) : key(k), re("\"" + std::string(k) + "\":\\s*([-0-9.eE+]+)") {}
  const char* key;
  std::regex re;
};

std::string base64(const std::vector<uchar>& data) {
  static const char* tbl = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  size_t i = 0;
  for (; i + 2 < data.size(); i += 3) {
    const unsigned v = (data[i] << 16) | (data[i + 1] << 8) | data[i + 2];
    out += {tbl[v >> 18], tbl[(v >> 12) & 63], tbl[(v >> 6) & 63], tbl[v & 63]};
  }
  if (i + 1 == data.size()) {
    const unsigned v = data[i] << 16;
    out += {tbl[v >> 18], tbl[(v >> 12) & 63], '=', '='};
  } else if (i + 2 == data.size()) {
    const unsigned v = (data[i] << 16) | (data[i + 1] << 8);
    out += {tbl[v >> 18], tbl[(v >> 12) & 63], tbl[(v >> 6) & 63], '='};
  }
  return out;
}

struct PlyPoint {
  float x, y, z;
  int r, g, b;
};

std::vector<PlyPoint> readPly(const fs::path& p) {
  std::ifstream in(p);
  std::string line;
  std::vector<PlyPoint> pts;
  bool body = false;
  while (std::getline(in, line)) {
    if (!body) {
      body = line == "end_header";
      continue;
    }
    std::istringstream ls(line);
    PlyPoint q;
    if (ls >> q.x >> q.y >> q.z >> q.r >> q.g >> q.b) pts.push_back(q);
  }
  return pts;
}

struct DynamicLine {
  double timestamp = 0, ratio = 0;
  int detected = 0, predicted = 0, dropped = 0;
  std::vector<std::pair<cv::Rect, bool>> boxes;  // box, predicted
};

/// The number under `key` in one line of dynamic.jsonl; InputError "file:N: ..." if it has none.
double numberIn(const std::string& line, const JsonNumberKey& key, const fs::path& p, int line_no) {
  std::smatch m;
  double v = 0;
  if (!std::regex_search(line, m, key.re) || !io::parseDouble(m[1].str(), v)) {
    throw InputError(fmt::format("{}:{}: no number \"{}\" in '{}'", p.string(), line_no, key.key, line.substr(0, 80)));
  }
  return v;
}

/// A count or pixel coordinate read as a double, clamped so the conversion to int is defined.
int clampedInt(double v) { return int(std::clamp(v, -1e9, 1e9)); }

std::vector<DynamicLine> readDynamic(const fs::path& p) {
  std::vector<DynamicLine> out;
  std::ifstream in(p);
  std::string line;
  static const JsonNumberKey timestamp_key("timestamp"), ratio_key("T"), dropped_key("dropped");
  static const std::regex box_re(
      "\\{\"x\": ([-0-9.]+), \"y\": ([-0-9.]+), \"w\": ([-0-9.]+), \"h\": ([-0-9.]+), \"class\": [0-9]+, "
      "\"score\": [0-9.]+, \"predicted\": (true|false)");
  for (int line_no = 1; std::getline(in, line); ++line_no) {
    DynamicLine d;
    d.timestamp = numberIn(line, timestamp_key, p, line_no);
    d.ratio = numberIn(line, ratio_key, p, line_no);
    d.dropped = clampedInt(numberIn(line, dropped_key, p, line_no));
    for (auto it = std::sregex_iterator(line.begin(), line.end(), box_re); it != std::sregex_iterator(); ++it) {
      const auto& m = *it;
      const bool pred = m[5] == "true";
      double xywh[4];
      for (int k = 0; k < 4; ++k) {
        if (!io::parseDouble(m[k + 1], xywh[k])) {
          throw InputError(fmt::format("{}:{}: bad box '{}'", p.string(), line_no, m.str().substr(0, 80)));
        }
      }
      d.boxes.push_back(
          {cv::Rect(clampedInt(xywh[0]), clampedInt(xywh[1]), clampedInt(xywh[2]), clampedInt(xywh[3])), pred});
      (pred ? d.predicted : d.detected)++;
    }
    out.push_back(std::move(d));
  }
  return out;
}

std::string sceneJson(const std::vector<PlyPoint>& pts, const std::vector<io::TrajectoryEntry>& traj,
                      const std::vector<io::TrajectoryEntry>& kfs) {
  std::string s = "{\"points\": [";
  const size_t step = std::max<size_t>(1, pts.size() / 20000);
  bool first = true;
  for (size_t i = 0; i < pts.size(); i += step) {
    s += fmt::format("{}{:.3f},{:.3f},{:.3f},{},{},{}", first ? "" : ",", pts[i].x, pts[i].y, pts[i].z, pts[i].r,
                     pts[i].g, pts[i].b);
    first = false;
  }
  s += "], \"trajectory\": [";
  for (size_t i = 0; i < traj.size(); ++i) {
    s += fmt::format("{}{:.4f},{:.4f},{:.4f}", i ? "," : "", traj[i].t.x(), traj[i].t.y(), traj[i].t.z());
  }
  s += "], \"frustums\": [";
  // Each keyframe: a small pyramid (camera centre to the four image corners at 5 cm).
  for (size_t k = 0; k < kfs.size(); ++k) {
    const Pose T = kfs[k].pose();
    const double d = 0.05, w = 0.04, h = 0.03;
    const Vec3 c = T.translation();
    const Vec3 a = T * Vec3(-w, -h, d), b = T * Vec3(w, -h, d), e = T * Vec3(w, h, d), f = T * Vec3(-w, h, d);
    std::string line;
    for (const Vec3& p : {c, a, b, c, e, f, c, a, f, e, b}) line += fmt::format("{:.4f},{:.4f},{:.4f},", p.x(), p.y(), p.z());
    line.pop_back();
    s += fmt::format("{}[{}]", k ? "," : "", line);
  }
  return s + "]}";
}

const char* const kPageHead =
    "<!DOCTYPE html><html><head><meta charset=\"utf-8\"><title>tkgslam report</title><style>"
    "body{font-family:sans-serif;margin:24px;max-width:1200px;color:#222}"
    "h2{border-bottom:1px solid #ccc;padding-bottom:4px;margin-top:28px}"
    "table{border-collapse:collapse}td,th{border:1px solid #ccc;padding:4px 10px;text-align:left}"
    ".row{display:flex;flex-wrap:wrap;gap:12px}pre{background:#f6f6f6;padding:10px;overflow:auto}"
    ".traj svg{width:540px;height:auto}canvas{border:1px solid #999;cursor:grab}.thumbs img{margin:2px;border:1px solid #999}"
    "</style><script>window.onerror=function(m){document.title='tkgslam report ERROR: '+m;};</script>"
    "</head><body>";

/// The accuracy against the dataset's ground truth: rows for the summary table and the figures.
struct AccuracySection {
  std::string rows, figures;
};

AccuracySection accuracySection(const std::string& dataset, const std::vector<io::TrajectoryEntry>& traj) {
  const fs::path gt_path = fs::path(dataset) / "groundtruth.txt";
  if (dataset.empty() || !fs::is_regular_file(gt_path) || traj.size() < 2) {
    return {"", "<p>No ground truth: accuracy plots omitted.</p>"};
  }
  std::vector<io::TrajectoryEntry> gt;
  eval::AteResult ate;
  try {
    gt = io::readTumTrajectory(gt_path.string());
    ate = eval::computeAte(gt, traj);
  } catch (const InputError& e) {
    // A ground truth that does not fit (another time unit, another sequence) costs the plots, not the report.
    return {"", fmt::format("<p>Ground truth not used: {}</p>", escapeXml(e.what()))};
  }
  AccuracySection a;
  a.rows = fmt::format("<tr><th>ATE RMSE</th><td>{:.4f} m ({} poses)</td></tr>", ate.stats.rmse, ate.stats.count);
  std::string rpe_figure;
  try {
    const auto rpe = eval::computeRpe(gt, traj, 1.0);
    a.rows += fmt::format("<tr><th>RPE RMSE (1 s)</th><td>{:.4f} m, {:.3f} deg</td></tr>", rpe.translation.rmse,
                          rpe.rotation_deg.rmse);
    Series s{"translational RPE (m)", "#d62728", {}, rpe.translation_errors};
    for (double t : rpe.timestamps) s.x.push_back(t - traj.front().timestamp);
    rpe_figure = svgLinePlot("RPE over time (1 s)", "time (s)", "m", {s});
  } catch (const InputError& e) {
    rpe_figure = fmt::format("<p>RPE not computed: {}.</p>", escapeXml(e.what()));
  }
  a.figures = "<h2>Trajectory vs ground truth</h2><div class=\"row traj\">";
  a.figures += eval::renderTrajectorySvg(ate, "top view", 0, 1);
  a.figures += eval::renderTrajectorySvg(ate, "side view", 0, 2);
  Series err{"ATE error (m)", "#1f77b4", {}, ate.errors};
  for (double t : ate.timestamps) err.x.push_back(t - ate.timestamps.front());
  a.figures += "</div><div class=\"row\">" + svgLinePlot("ATE error over time", "time (s)", "m", {err}) + rpe_figure + "</div>";
  return a;
}

/// Mean time per stage from timing.json (stages without a number are left out).
std::string timingSection(const fs::path& timing_json) {
  const YAML::Node timing = parseJson(slurp(timing_json), timing_json.string());
  std::vector<std::pair<std::string, double>> bars;
  if (timing.IsMap()) {
    for (const auto& stage : timing) {
      double ms = 0;
      if (io::parseDouble(scalarText(stage.second, "mean_ms"), ms)) bars.emplace_back(stage.first.Scalar(), ms);
    }
  }
  return "<h2>Time per frame</h2>" + svgBarChart("mean per stage (detector: per run)", bars, "ms");
}

std::string sceneSection(const std::vector<PlyPoint>& pts, const std::vector<io::TrajectoryEntry>& traj,
                         const std::vector<io::TrajectoryEntry>& kfs) {
  return "<h2>3-D map</h2><p>Map points coloured by height, keyframes (yellow), trajectory (red). Drag to orbit, "
         "wheel to zoom.</p><canvas id=\"view3d\" width=\"900\" height=\"560\"></canvas>"
         "<script id=\"scene\" type=\"application/json\">" +
         sceneJson(pts, traj, kfs) + "</script>";
}

/// Plots of the ratio T against the threshold `tau`, the boxes and the dropped keypoints over time.
std::string dynamicPlots(const std::vector<DynamicLine>& dyn, double tau_value) {
  Series ratio{"T (box area / image)", "#9467bd", {}, {}}, tau{"tau", "#999", {}, {}};
  Series det{"detected", "#1f77b4", {}, {}}, pred{"Kalman-filled", "#ff7f0e", {}, {}};
  Series drop{"dropped keypoints", "#2ca02c", {}, {}};
  for (const auto& d : dyn) {
    const double t = d.timestamp - dyn.front().timestamp;
    ratio.x.push_back(t), ratio.y.push_back(d.ratio);
    det.x.push_back(t), det.y.push_back(d.detected);
    pred.x.push_back(t), pred.y.push_back(d.predicted);
    drop.x.push_back(t), drop.y.push_back(d.dropped);
  }
  tau.x = {0.0, ratio.x.back()};
  tau.y = {tau_value, tau_value};
  return "<h2>Dynamic objects</h2><div class=\"row\">" + svgLinePlot("ratio T over time", "time (s)", "T", {ratio, tau}) +
         svgLinePlot("boxes per frame", "time (s)", "boxes", {det, pred}) +
         svgLinePlot("keypoints dropped per frame", "time (s)", "keypoints", {drop}) + "</div>";
}

/// Eight frames spread over the run, with their boxes drawn (red detected, orange Kalman-filled).
std::string thumbnails(const std::string& dataset, const std::vector<DynamicLine>& dyn) {
  try {
    io::TumDataset ds(dataset);
    std::map<long long, const DynamicLine*> by_stamp;
    for (const auto& d : dyn) by_stamp[std::llround(d.timestamp * 1e6)] = &d;
    std::string html = "<div class=\"thumbs\">";
    const int n = std::min(ds.size(), int(dyn.size()));
    for (int k = 0; k < 8 && n > 0; ++k) {
      const int i = int((long long)k * (n - 1) / 7);
      auto img = ds.load(i);
      auto it = by_stamp.find(std::llround(img.timestamp * 1e6));
      if (it != by_stamp.end()) {
        for (const auto& [box, predicted] : it->second->boxes) {
          cv::rectangle(img.bgr, box, predicted ? cv::Scalar(0, 165, 255) : cv::Scalar(0, 0, 255), 3);
        }
      }
      cv::Mat small;
      cv::resize(img.bgr, small, cv::Size(200, 150), 0, 0, cv::INTER_AREA);
      std::vector<uchar> jpg;
      cv::imencode(".jpg", small, jpg, {cv::IMWRITE_JPEG_QUALITY, 80});
      html += fmt::format("<img width=\"200\" height=\"150\" title=\"{:.3f}\" src=\"data:image/jpeg;base64,{}\">",
                          img.timestamp, base64(jpg));
    }
    return html + "</div><p>Red: detected boxes; orange: filled in by the Kalman tracker.</p>";
  } catch (const InputError& e) {
    return fmt::format("<p>Thumbnails unavailable: {}</p>", escapeXml(e.what()));
  }
}

/// The dynamic-objects section, empty for a run without dynamic.jsonl (or an empty one).
std::string dynamicSection(const fs::path& dynamic_jsonl, const YAML::Node& run, const std::string& dataset) {
  if (!fs::is_regular_file(dynamic_jsonl)) return "";
  const auto dyn = readDynamic(dynamic_jsonl);
  if (dyn.empty()) return "";
  double tau = 0.7;  // the default, for run.json files written before the threshold was recorded
  if (double v = 0; io::parseDouble(scalarText(run, "ratio_threshold"), v)) tau = v;
  std::string html = dynamicPlots(dyn, tau);
  if (fs::is_directory(dataset)) html += thumbnails(dataset, dyn);
  return html;
}

}  // namespace

std::string writeHtmlReport(const std::string& out_dir) {
  const fs::path dir(out_dir);
  if (!fs::is_regular_file(dir / "trajectory.txt") || !fs::is_regular_file(dir / "run.json")) {
    throw InputError(fmt::format("'{}' is not the output folder of `tkgslam run` (no trajectory.txt / run.json)", out_dir));
  }
  const YAML::Node run = parseJson(slurp(dir / "run.json"), (dir / "run.json").string());
  const auto traj = io::readTumTrajectory((dir / "trajectory.txt").string());
  const auto kfs = fs::exists(dir / "keyframes.txt") ? io::readTumTrajectory((dir / "keyframes.txt").string())
                                                      : std::vector<io::TrajectoryEntry>{};
  const std::string dataset = scalarText(run, "dataset");
  const std::string mode = scalarText(run, "mode");

  std::string html = kPageHead;
  html += fmt::format("<h1>tkgslam run report</h1><p>Sequence <code>{}</code>, dynamic mode <b>{}</b>.</p>",
                      escapeXml(dataset), escapeXml(mode));
  html += "<h2>Summary</h2><table>";
  for (const char* k : {"frames", "tracked", "tracked_ratio", "skipped", "keyframes", "map_points", "mean_ms_per_frame",
                        "median_ms_per_frame"}) {
    html += fmt::format("<tr><th>{}</th><td>{}</td></tr>", k, escapeXml(scalarText(run, k)));
  }
  const AccuracySection accuracy = accuracySection(dataset, traj);
  html += accuracy.rows + "</table>" + accuracy.figures;
  html += timingSection(dir / "timing.json");
  html += sceneSection(readPly(dir / "map.ply"), traj, kfs);
  html += dynamicSection(dir / "dynamic.jsonl", run, dataset);
  html += "<h2>Configuration</h2><pre>" + escapeXml(slurp(dir / "config_used.yaml")) + "</pre>";
  html += std::string("<script>") + kViewerScript + "document.title='tkgslam report ready';</script></body></html>\n";
  const auto path = (dir / "report.html").string();
  io::writeOutputFile(path, "report", html);
  return path;
}

}  // namespace tkgslam::report
