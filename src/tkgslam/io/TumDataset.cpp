#include "tkgslam/io/TumDataset.h"

#include <filesystem>
#include <fstream>
#include <limits>

#include <fmt/format.h>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "tkgslam/common/Error.h"
#include "tkgslam/eval/Association.h"
#include "tkgslam/io/ColourImage.h"
#include "tkgslam/io/TextParsing.h"
#include "tkgslam/io/InputFile.h"

namespace fs = std::filesystem;

namespace tkgslam::io {

namespace {

double parseTimestamp(const std::string& token, const std::string& source, int line_no) {
  double t = 0;
  if (!parseDouble(token, t) || t < 0) {
    throw InputError(fmt::format("{}:{}: malformed timestamp '{}'", source, line_no, token));
  }
  return t;
}

void requireAfter(double t, const std::string& token, double previous, const std::string& source, int line_no) {
  if (t <= previous) {
    throw InputError(fmt::format("{}:{}: timestamp {} is not after the previous one ({}); timestamps must increase",
                                 source, line_no, token, previous));
  }
}

}  // namespace

std::vector<ListEntry> parseTumImageList(std::istream& in, const std::string& source) {
  std::vector<ListEntry> out;
  for (const auto& l : readDataLines(in, source, 2, "timestamp filename")) {
    const double t = parseTimestamp(l.fields[0], source, l.number);
    if (!out.empty()) requireAfter(t, l.fields[0], out.back().timestamp, source, l.number);
    out.push_back({t, l.fields[1]});
  }
  return out;
}

std::vector<AssociationLine> parseAssociationFile(std::istream& in, const std::string& source) {
  std::vector<AssociationLine> out;
  for (const auto& l : readDataLines(in, source, 4, "timestamp filename timestamp filename")) {
    AssociationLine a;
    a.line = l.number;
    a.first = {parseTimestamp(l.fields[0], source, l.number), l.fields[1]};
    a.second = {parseTimestamp(l.fields[2], source, l.number), l.fields[3]};
    if (!out.empty()) requireAfter(a.first.timestamp, l.fields[0], out.back().first.timestamp, source, l.number);
    out.push_back(std::move(a));
  }
  return out;
}

namespace {

std::vector<ListEntry> readList(const fs::path& path) {
  if (!fs::exists(path)) {
    throw InputError(fmt::format("missing image list '{}' (a TUM sequence has rgb.txt and depth.txt; or give "
                                 "an association file with --associations)",
                                 path.string()));
  }
  std::ifstream in = openInputFile(path.string(), "image list");
  auto list = parseTumImageList(in, path.string());
  if (list.empty()) throw InputError(fmt::format("image list '{}' has no entries", path.string()));
  return list;
}

std::vector<double> stamps(const std::vector<ListEntry>& list) {
  std::vector<double> s;
  s.reserve(list.size());
  for (const auto& e : list) s.push_back(e.timestamp);
  return s;
}

/// What load() takes for depth: single-channel 16-bit (or 32-bit float metres).
bool isDepthType(const cv::Mat& image) { return image.type() == CV_16UC1 || image.type() == CV_32FC1; }

/// Whether the image file is a depth image. Throws for an unreadable file.
bool isDepthImage(const std::string& path) {
  const cv::Mat m = cv::imread(path, cv::IMREAD_UNCHANGED);
  if (m.empty()) throw InputError(fmt::format("cannot read image '{}'", path));
  return isDepthType(m);
}

}  // namespace

TumDataset::TumDataset(const std::string& directory, TumDatasetOptions options)
    : directory_(directory), options_(options) {
  if (options_.depth_factor <= 0) throw InputError("depth factor must be > 0");
  if (options_.loops < 1) throw InputError("loops must be >= 1");
  const fs::path dir(directory);
  if (!fs::is_directory(dir)) throw InputError(fmt::format("dataset folder '{}' does not exist", directory));
  if (options_.associations.empty()) {
    associateLists();
  } else {
    readAssociationFile();
  }
  if (options_.expected_width > 0) {
    // A camera config for another sensor fails every frame: say so once, here, rather than skipping
    // the whole sequence frame by frame. (An unreadable first image is left to load().)
    const cv::Mat first = cv::imread(entries_.front().rgb_path, cv::IMREAD_UNCHANGED);
    if (!first.empty() && !fitsCamera(first.size())) {
      throw InputError(fmt::format("the images of '{}' are {}x{} but the camera config says {}x{}: a config "
                                   "for another camera?",
                                   directory, first.cols, first.rows, options_.expected_width,
                                   options_.expected_height));
    }
  }
  if (options_.loops > std::numeric_limits<int>::max() / int(entries_.size())) {
    throw InputError(fmt::format("{} loops of the {} frames of '{}' are more frames than a run can count (2^31)",
                                 options_.loops, entries_.size(), directory));
  }
  has_masks_ = fs::is_directory(dir / "masks");
  const double span = entries_.back().rgb_timestamp - entries_.front().rgb_timestamp;
  loop_period_ = span + (entries_.size() > 1 ? span / double(entries_.size() - 1) : 1.0);
}

void TumDataset::associateLists() {
  const fs::path dir(directory_);
  const auto rgb = readList(dir / "rgb.txt");
  const auto depth = readList(dir / "depth.txt");
  const auto pairs = eval::associateTimestamps(stamps(rgb), stamps(depth), options_.max_time_difference);
  if (pairs.empty()) {
    throw InputError(fmt::format("no RGB image in '{}' has a depth image within {} s; "
                                 "check rgb.txt and depth.txt",
                                 directory_, options_.max_time_difference));
  }
  for (const auto& [i, j] : pairs) {
    RgbdEntry e;
    e.rgb_timestamp = rgb[i].timestamp;
    e.depth_timestamp = depth[j].timestamp;
    e.rgb_path = (dir / rgb[i].file).string();
    e.depth_path = (dir / depth[j].file).string();
    for (const auto* p : {&e.rgb_path, &e.depth_path}) {
      if (!fs::is_regular_file(*p)) {
        throw InputError(fmt::format("listed image '{}' does not exist ({})", *p,
                                     p == &e.rgb_path ? "rgb.txt" : "depth.txt"));
      }
    }
    entries_.push_back(std::move(e));
  }
}

void TumDataset::readAssociationFile() {
  const std::string& file = options_.associations;
  std::ifstream in = openInputFile(file, "association file");
  const auto lines = parseAssociationFile(in, file);
  if (lines.empty()) throw InputError(fmt::format("association file '{}' has no entries", file));
  // Names are relative to the sequence folder, as ORB-SLAM2 reads them (absolute ones stay).
  const fs::path dir(directory_);
  const auto path = [&](const ListEntry& e) { return (dir / e.file).string(); };
  for (const auto& l : lines) {
    for (const auto* e : {&l.first, &l.second}) {
      if (!fs::is_regular_file(path(*e))) {
        throw InputError(fmt::format("{}:{}: image '{}' does not exist", file, l.line, path(*e)));
      }
    }
  }
  // associate.py writes the list given first in the first column (RGB in ORB-SLAM2's examples, but
  // either is common): the images say which is which.
  const bool first_is_depth = isDepthImage(path(lines[0].first));
  if (first_is_depth == isDepthImage(path(lines[0].second))) {
    throw InputError(fmt::format("{}:{}: cannot tell the depth image from the colour one: '{}' and '{}' are {} "
                                 "single-channel 16-bit images",
                                 file, lines[0].line, path(lines[0].first), path(lines[0].second),
                                 first_is_depth ? "both" : "neither"));
  }
  for (const auto& l : lines) {
    const ListEntry& rgb = first_is_depth ? l.second : l.first;
    const ListEntry& depth = first_is_depth ? l.first : l.second;
    // The frames' timestamps are the colour images'; the parser checked the first column only.
    if (!entries_.empty() && rgb.timestamp <= entries_.back().rgb_timestamp) {
      throw InputError(fmt::format("{}:{}: colour timestamp {} is not after the previous one ({}); timestamps must "
                                   "increase",
                                   file, l.line, rgb.timestamp, entries_.back().rgb_timestamp));
    }
    entries_.push_back({rgb.timestamp, depth.timestamp, path(rgb), path(depth)});
  }
}

bool TumDataset::fitsCamera(const cv::Size& image) const {
  return options_.expected_width <= 0 ||
         (image.width == options_.expected_width && image.height == options_.expected_height);
}

double TumDataset::timestamp(int i) const {
  const int n = framesPerLoop();
  return entries_[i % n].rgb_timestamp + loop_period_ * (i / n);
}

RgbdImages TumDataset::load(int i) const {
  if (i < 0 || i >= size()) throw InputError(fmt::format("frame index {} out of range", i));
  const RgbdEntry& e = entry(i);
  RgbdImages out;
  out.timestamp = timestamp(i);
  out.bgr = readColourImage(e.rgb_path, "RGB image");
  cv::cvtColor(out.bgr, out.gray, cv::COLOR_BGR2GRAY);
  cv::Mat raw = cv::imread(e.depth_path, cv::IMREAD_UNCHANGED);
  if (raw.empty()) throw InputError(fmt::format("cannot read depth image '{}'", e.depth_path));
  if (!isDepthType(raw)) {
    throw InputError(fmt::format("depth image '{}' must be single-channel 16-bit (or 32-bit float "
                                 "metres); it is {}",
                                 e.depth_path, describePixels(raw)));
  }
  if (raw.size() != out.bgr.size()) {
    throw InputError(fmt::format("depth image '{}' is {}x{} but the RGB image is {}x{}", e.depth_path,
                                 raw.cols, raw.rows, out.bgr.cols, out.bgr.rows));
  }
  if (!fitsCamera(out.bgr.size())) {
    throw InputError(fmt::format("image '{}' is {}x{} but the camera config says {}x{}", e.rgb_path,
                                 out.bgr.cols, out.bgr.rows, options_.expected_width,
                                 options_.expected_height));
  }
  if (has_masks_) {
    const auto mask_path = fs::path(directory_) / "masks" / (fs::path(e.rgb_path).stem().string() + ".png");
    out.truth_mask = cv::imread(mask_path.string(), cv::IMREAD_GRAYSCALE);
    if (out.truth_mask.size() != out.bgr.size()) out.truth_mask.release();
  }
  if (raw.type() == CV_16UC1) {
    raw.convertTo(out.depth_m, CV_32F, 1.0 / options_.depth_factor);
  } else {
    out.depth_m = raw;
    cv::patchNaNs(out.depth_m, 0.0);
  }
  return out;
}

std::optional<std::string> TumDataset::groundTruthPath() const {
  const fs::path p = fs::path(directory_) / "groundtruth.txt";
  if (fs::is_regular_file(p)) return p.string();
  return std::nullopt;
}

}  // namespace tkgslam::io
