#pragma once
// Entry points shared by the libFuzzer targets (fuzz/*Fuzzer.cpp) and the regression test that
// replays every input in fuzz/regressions/ (tests/io/FuzzRegressionTest.cpp).
// Each harness feeds arbitrary bytes to one user-facing parser. InputError is the parser's
// documented answer to bad input and is swallowed; anything else (another exception, a crash,
// a sanitizer report, a hang) is a bug.
#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>
#include <vector>

#include "tkgslam/common/Error.h"
#include "tkgslam/dynamic/OnnxSiluFusion.h"
#include "tkgslam/dynamic/ProtobufWire.h"
#include "tkgslam/eval/Association.h"
#include "tkgslam/io/ConfigFile.h"
#include "tkgslam/io/MapFile.h"
#include "tkgslam/io/TrajectoryFile.h"
#include "tkgslam/io/TumDataset.h"

namespace tkgslam::fuzz {

/// rgb.txt and depth.txt in one input, split at the first NUL byte (absent: the same text twice),
/// parsed and associated as TumDataset does; and the whole input as an association file.
inline void fuzzTumLists(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  const auto split = text.find('\0');
  const std::string rgb_text = text.substr(0, split);
  const std::string depth_text = split == std::string::npos ? text : text.substr(split + 1);
  try {
    std::istringstream rgb_in(rgb_text), depth_in(depth_text);
    const auto rgb = io::parseTumImageList(rgb_in, "rgb.txt");
    const auto depth = io::parseTumImageList(depth_in, "depth.txt");
    std::vector<double> a, b;
    for (const auto& e : rgb) a.push_back(e.timestamp);
    for (const auto& e : depth) b.push_back(e.timestamp);
    for (const auto& [i, j] : eval::associateTimestamps(a, b)) {
      if (i < 0 || j < 0 || i >= static_cast<int>(a.size()) || j >= static_cast<int>(b.size())) {
        __builtin_trap();  // an association outside the lists is a bug
      }
    }
    if (!a.empty()) (void)eval::findClosestIndex(a, b.empty() ? 0.0 : b.front());
  } catch (const InputError&) {
  }
  try {
    std::istringstream in(text);
    const auto lines = io::parseAssociationFile(in, "associations.txt");
    for (size_t k = 1; k < lines.size(); ++k) {
      if (!(lines[k].first.timestamp > lines[k - 1].first.timestamp)) __builtin_trap();  // promised increasing
    }
  } catch (const InputError&) {
  }
}

/// A TUM trajectory as `tkgslam eval` reads it, including each pose's conversion.
inline void fuzzTrajectory(const std::uint8_t* data, std::size_t size) {
  try {
    std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
    for (const auto& entry : io::parseTumTrajectory(in, "trajectory.txt")) {
      if (!entry.hasZeroQuaternion()) (void)entry.pose();
    }
  } catch (const InputError&) {
  }
}

/// A YAML config as `tkgslam run -c` reads it; one it accepts must also survive being written out
/// (config_used.yaml) and read back: the same text again, so the same values.
inline void fuzzConfig(const std::uint8_t* data, std::size_t size) {
  // Before the first NUL byte the file; after it, one `run --set` override per line.
  const std::string text(reinterpret_cast<const char*>(data), size);
  const auto split = text.find('\0');
  std::vector<std::string> overrides;
  if (split != std::string::npos) {
    std::istringstream lines(text.substr(split + 1));
    for (std::string line; std::getline(lines, line);) overrides.push_back(line);
  }
  SlamConfig config;
  try {
    config = io::parseConfig(text.substr(0, split), "config.yaml", overrides);
  } catch (const InputError&) {
    return;
  }
  const std::string written = io::configToYaml(config);
  try {
    if (io::configToYaml(io::parseConfig(written, "config.yaml")) != written) __builtin_trap();
  } catch (const InputError&) {
    __builtin_trap();  // a config it accepted, written out, must be accepted again
  }
}

/// The camera and pyramid of configs/tum_fr1.yaml, which the map-file seeds were made with.
inline camera::CameraParams fuzzMapCamera() {
  camera::CameraParams c;
  c.fx = 517.306408;
  c.fy = 516.469215;
  c.cx = 318.643040;
  c.cy = 255.313989;
  c.distortion = {0.262383, -0.953104, -0.005358, 0.002628, 1.163314};
  return c;
}

/// A map file as `tkgslam run --load-map` reads it. One it accepts must be consistent (every
/// observation in its keyframe's slot) and survive being written and read again unchanged.
inline void fuzzMapFile(const std::uint8_t* data, std::size_t size) {
  static const camera::PinholeCamera camera(fuzzMapCamera());
  static const auto pyramid = feature::ScalePyramid::make(8, 1.2);
  data::Map map;
  try {
    io::deserializeMap(std::string_view(reinterpret_cast<const char*>(data), size), map, camera, pyramid);
  } catch (const InputError&) {
    if (map.keyFrameCount() + map.mapPointCount() != 0) __builtin_trap();  // refused, yet half-loaded
    return;
  }
  for (const auto& mp : map.mapPoints()) {
    for (const auto& [kf, idx] : mp->observations) {
      if (idx < 0 || size_t(idx) >= kf->map_points.size() || kf->map_points[idx].get() != mp.get()) __builtin_trap();
    }
  }
  const std::string written = io::serializeMap(map, camera, pyramid);
  data::Map again;
  try {
    io::deserializeMap(written, again, camera, pyramid);
  } catch (const InputError&) {
    __builtin_trap();  // a map it accepted, written out, must be accepted again
  }
  if (io::serializeMap(again, camera, pyramid) != written) __builtin_trap();
}

/// An ONNX model file (`dynamic.model`) through the SiLU fusion the detector runs before OpenCV reads
/// it. A model it does not change comes back byte for byte; one it changes must be a well-formed
/// message with nothing left to fuse.
inline void fuzzOnnxGraph(const std::uint8_t* data, std::size_t size) {
  const std::vector<uchar> model(data, data + size);
  const dynamic::SiluFusion result = dynamic::fuseSiluNodes(model, "Silu");
  if (result.fused == 0) {
    if (result.model != model) __builtin_trap();
    return;
  }
  std::vector<dynamic::WireField> fields;
  const std::string_view out(reinterpret_cast<const char*>(result.model.data()), result.model.size());
  if (!dynamic::splitWireFields(out, fields)) __builtin_trap();
  if (dynamic::fuseSiluNodes(result.model, "Silu").fused != 0) __builtin_trap();
}

}  // namespace tkgslam::fuzz
