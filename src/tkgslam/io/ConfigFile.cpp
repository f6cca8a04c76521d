#include "tkgslam/io/ConfigFile.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <type_traits>
#include <set>
#include <sstream>
#include <vector>

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include "tkgslam/common/Error.h"
#include "tkgslam/io/InputFile.h"

namespace tkgslam::io {

namespace {

// A mapping key as text. YAML allows any node as a key ("? [a, b]: 1"); ours are plain words.
std::string keyName(const YAML::Node& key, const std::string& source, const std::string& where) {
  if (!key.IsScalar()) throw InputError(fmt::format("{}: {} has a key that is not a plain word", source, where));
  return key.Scalar();
}

template <typename T>
bool isFinite(const T& value) {
  if constexpr (std::is_floating_point_v<T>) {
    return std::isfinite(value);
  } else if constexpr (std::is_same_v<T, std::vector<double>>) {
    for (double v : value) {
      if (!std::isfinite(v)) return false;
    }
  }
  return true;
}

/// What a key of type T takes, in words for an error message.
template <typename T>
const char* kindOf() {
  if constexpr (std::is_same_v<T, bool>) {
    return "true or false";
  } else if constexpr (std::is_integral_v<T>) {
    return "a whole number";
  } else if constexpr (std::is_floating_point_v<T>) {
    return "a number";
  } else if constexpr (std::is_same_v<T, std::vector<int>>) {
    return "a list of whole numbers, e.g. [0, 1]";
  } else if constexpr (std::is_same_v<T, std::vector<double>>) {
    return "a list of numbers";
  } else {
    return "a text";
  }
}

/// A node as written in the file, shortened for an error message.
std::string shownValue(const YAML::Node& node) {
  std::string text = YAML::Dump(node);
  for (char& c : text) {
    if (c == '\n') c = ' ';
  }
  return text.size() > 40 ? text.substr(0, 37) + "..." : text;
}

// yaml-cpp keeps both entries of a key written twice and lookups return the first, so a value
// appended to the end of a config to override one above would be ignored without a word.
void checkNoDuplicateKeys(const YAML::Node& map, const std::string& source, const std::string& prefix,
                          const std::string& where) {
  std::map<std::string, int> line_of;
  for (const auto& kv : map) {
    const auto key = keyName(kv.first, source, where);
    const int line = kv.first.Mark().line + 1;
    if (const auto [it, fresh] = line_of.emplace(key, line); !fresh) {
      throw InputError(fmt::format("{}: '{}{}' is set twice (lines {} and {})", source, prefix, key, it->second, line));
    }
  }
}

void require(bool ok, const std::string& source, const std::string& what) {
  if (!ok) throw InputError(fmt::format("{}: {}", source, what));
}

const std::vector<std::string> kSections = {"camera", "depth", "orb", "tracking", "mapping", "loop", "dynamic", "system"};

// A section's keys set on the command line (`run --set`), each with the override's text.
using Overridden = std::map<std::string, std::string>;

std::string unknownOverride(const std::string& text, const std::string& section, const std::string& key) {
  return fmt::format("--set '{}': unknown key '{}.{}' (the keys are listed in the README's config format and in any "
                     "run's config_used.yaml)",
                     text, section, key);
}

// Reads one mapping section, remembering which keys were used so leftovers can be reported.
class Section {
 public:
  /// `overridden`: this section's keys set on the command line (their errors name the override);
  /// `checked`: what range errors name (the file and the overrides).
  Section(const YAML::Node& root, std::string name, std::string source, bool required, Overridden overridden = {},
          std::string checked = {})
      : name_(std::move(name)),
        source_(std::move(source)),
        checked_(checked.empty() ? source_ : std::move(checked)),
        overridden_(std::move(overridden)) {
    const YAML::Node found = static_cast<const YAML::Node&>(root)[name_];
    if (!found || found.IsNull()) {
      if (required) throw InputError(fmt::format("{}: missing section '{}'", source_, name_));
      return;
    }
    node_.reset(found);
    present_ = true;
    if (!node_.IsMap()) throw InputError(fmt::format("{}: section '{}' must be a mapping", source_, name_));
    checkNoDuplicateKeys(node_, source_, name_ + ".", "section '" + name_ + "'");
  }

  template <typename T>
  void get(const std::string& key, T& value, bool required = false) {
    used_.insert(key);
    const YAML::Node& section = node_;
    if (!present_ || !section[key]) {
      if (required) throw InputError(fmt::format("{}: missing key '{}.{}'", source_, name_, key));
      return;
    }
    T parsed;
    try {
      parsed = section[key].template as<T>();
    } catch (const YAML::Exception&) {
      const auto o = overridden_.find(key);
      if (o != overridden_.end()) {
        throw InputError(fmt::format("--set {}: invalid value, it takes {}", o->second, kindOf<T>()));
      }
      throw InputError(fmt::format("{}:{}: key '{}.{}' has an invalid value '{}': it takes {}", source_,
                                   section[key].Mark().line + 1, name_, key, shownValue(section[key]), kindOf<T>()));
    }
    // .nan/.inf parse as doubles but would pass or poison every later range check.
    if (!isFinite(parsed)) throw InputError(fmt::format("{}: key '{}.{}' must be finite", source_, name_, key));
    value = std::move(parsed);
  }

  void require(bool ok, const std::string& what) const { io::require(ok, checked_, what); }

  void checkNoUnknownKeys() const {
    if (!present_) return;
    for (const auto& kv : node_) {
      const auto key = keyName(kv.first, source_, "section '" + name_ + "'");
      if (used_.count(key)) continue;
      const auto o = overridden_.find(key);
      if (o != overridden_.end()) throw InputError(unknownOverride(o->second, name_, key));
      throw InputError(fmt::format("{}: unknown key '{}.{}'", source_, name_, key));
    }
  }

 private:
  YAML::Node node_;
  bool present_ = false;
  std::string name_, source_, checked_;
  Overridden overridden_;
  std::set<std::string> used_;
};

constexpr bool kRequired = true;

// Every key of a config file, once, in the order it is written: parseConfig reads them, configToYaml
// writes them, so a key added here is both read and recorded in each run's config_used.yaml.
// `key(section, name, field, required)`; Config is SlamConfig or const SlamConfig.
template <typename Config, typename Visit>
void forEachKey(Config& c, Visit&& key) {
  key("camera", "width", c.camera.width, kRequired);
  key("camera", "height", c.camera.height, kRequired);
  key("camera", "fx", c.camera.fx, kRequired);
  key("camera", "fy", c.camera.fy, kRequired);
  key("camera", "cx", c.camera.cx, kRequired);
  key("camera", "cy", c.camera.cy, kRequired);
  key("camera", "distortion", c.camera.distortion, false);
  key("camera", "fps", c.camera.fps, false);
  key("depth", "factor", c.depth.factor, false);
  key("depth", "baseline_fx", c.depth.baseline_fx, false);
  key("depth", "close_threshold", c.depth.close_threshold, false);
  key("depth", "max_depth", c.depth.max_depth, false);
  key("orb", "features", c.orb.features, false);
  key("orb", "scale_factor", c.orb.scale_factor, false);
  key("orb", "levels", c.orb.levels, false);
  key("orb", "fast_threshold", c.orb.fast_threshold, false);
  key("orb", "fast_min_threshold", c.orb.fast_min_threshold, false);
  auto& tr = c.tracking;
  key("tracking", "min_init_features", tr.min_init_features, false);
  key("tracking", "min_tracked_inliers", tr.min_tracked_inliers, false);
  key("tracking", "max_frames_between_keyframes", tr.max_frames_between_keyframes, false);
  key("tracking", "relocalization_attempts", tr.relocalization_attempts, false);
  key("tracking", "relocalization_candidates", tr.relocalization_candidates, false);
  key("tracking", "max_predicted_frames", tr.max_predicted_frames, false);
  key("tracking", "reanchor_segments", tr.reanchor_segments, false);
  key("tracking", "blur_ratio", tr.blur_ratio, false);
  key("tracking", "max_jump_deg", tr.max_jump_deg, false);
  key("tracking", "max_jump_m", tr.max_jump_m, false);
  key("tracking", "covered_ratio", tr.covered_ratio, false);
  key("tracking", "min_rescued_inliers", tr.min_rescued_inliers, false);
  key("tracking", "pose_check_m", tr.pose_check_m, false);
  key("tracking", "excursion_m", tr.excursion_m, false);
  key("mapping", "local_ba_iterations", c.mapping.local_ba_iterations, false);
  key("mapping", "covisible_keyframes", c.mapping.covisible_keyframes, false);
  key("mapping", "keyframe_redundancy", c.mapping.keyframe_redundancy, false);
  key("mapping", "max_keyframe_shift_m", c.mapping.max_keyframe_shift_m, false);
  key("mapping", "max_keyframe_shift_deg", c.mapping.max_keyframe_shift_deg, false);
  key("mapping", "cull_keyframes", c.mapping.cull_keyframes, false);
  key("loop", "enabled", c.loop.enabled, false);
  key("loop", "confirm", c.loop.confirm, false);
  key("loop", "confirm_within", c.loop.confirm_within, false);
  key("loop", "min_inliers", c.loop.min_inliers, false);
  key("loop", "min_keyframe_gap", c.loop.min_keyframe_gap, false);
  key("loop", "candidates", c.loop.candidates, false);
  key("loop", "word_candidates", c.loop.word_candidates, false);
  key("loop", "min_correction_m", c.loop.min_correction_m, false);
  key("loop", "min_correction_deg", c.loop.min_correction_deg, false);
  key("loop", "global_ba_iterations", c.loop.global_ba_iterations, false);
  auto& dy = c.dynamic;
  auto& d = dy.detector;
  key("dynamic", "mode", dy.mode, false);
  key("dynamic", "model", d.model, false);
  key("dynamic", "input_size", d.input_size, false);
  key("dynamic", "extra_input_size", d.extra_input_size, false);
  key("dynamic", "fit_input", d.fit_input, false);
  key("dynamic", "confidence", d.confidence, false);
  key("dynamic", "person_confidence", d.person_confidence, false);
  key("dynamic", "nms", d.nms, false);
  key("dynamic", "classes", d.classes, false);
  key("dynamic", "detect_every", dy.detect_every, false);
  key("dynamic", "detector_latency", dy.detector_latency, false);
  key("dynamic", "box_margin", dy.box_margin, false);
  key("dynamic", "object_mask", dy.object_mask, false);
  key("dynamic", "object_behind", dy.object.behind, false);
  key("dynamic", "object_behind_per_size", dy.object.behind_per_size, false);
  key("dynamic", "object_radius", dy.object.radius, false);
  key("dynamic", "object_colour", dy.object.colour, false);
  key("dynamic", "object_region", dy.object.region, false);
  key("dynamic", "object_region_step", dy.object.region_step, false);
  key("dynamic", "box_flow", dy.box_flow, false);
  key("dynamic", "lookahead", dy.lookahead, false);
  key("dynamic", "detector_tiles", dy.detector_tiles, false);
  key("dynamic", "refill_ratio", dy.refill_ratio, false);
  key("dynamic", "late_culling", dy.late_culling, false);
  auto& t = dy.tracker;
  key("dynamic", "kalman_q", t.kalman.q, false);
  key("dynamic", "kalman_r", t.kalman.r, false);
  key("dynamic", "iou_gate", t.iou_gate, false);
  key("dynamic", "centre_gate", t.centre_gate, false);
  key("dynamic", "centre_gate_max", t.centre_gate_max, false);
  key("dynamic", "max_age", t.max_age, false);
  auto& g = dy.geometry;
  key("dynamic", "ratio_threshold", g.ratio_threshold, false);
  key("dynamic", "reference_keyframes", g.reference_keyframes, false);
  key("dynamic", "reference_max_depth", g.reference_max_depth, false);
  key("dynamic", "current_max_depth", g.current_max_depth, false);
  key("dynamic", "max_parallax_deg", g.max_parallax_deg, false);
  key("dynamic", "occlusion_threshold", g.occlusion_threshold, false);
  key("dynamic", "patch_radius", g.patch_radius, false);
  key("dynamic", "max_patch_std", g.max_patch_std, false);
  key("dynamic", "region_depth_step", g.region_depth_step, false);
  key("dynamic", "occluder_radius", g.occluder_radius, false);
  key("dynamic", "occluder_depth", g.occluder_depth, false);
  key("dynamic", "unboxed_check", g.unboxed_check, false);
  key("dynamic", "unboxed_min_evidence", g.unboxed_min_evidence, false);
  key("dynamic", "unboxed_depth_range", g.unboxed_depth_range, false);
  key("dynamic", "unboxed_min_hidden", g.unboxed_min_hidden, false);
  key("system", "deterministic", c.deterministic, false);
  key("system", "seed", c.seed, false);
  key("system", "opencv_threads", c.opencv_threads, false);
}

// Range checks, one function per section; each throws InputError "<source>: <what>".

void checkCameraDepthOrb(const SlamConfig& c, const std::string& source) {
  try {
    camera::PinholeCamera check(c.camera);
  } catch (const InputError& e) {
    throw InputError(fmt::format("{}: {}", source, e.what()));
  }
  require(c.depth.factor > 0, source, "depth.factor must be > 0");
  require(c.depth.baseline_fx > 0, source, "depth.baseline_fx must be > 0");
  require(c.depth.close_threshold > 0, source, "depth.close_threshold must be > 0");
  require(c.depth.max_depth > 0, source, "depth.max_depth must be > 0");
  try {
    feature::OrbExtractor check(c.orb);
  } catch (const InputError& e) {
    throw InputError(fmt::format("{}: {}", source, e.what()));
  }
}

void checkTracking(const TrackingParams& t, const std::string& source) {
  require(t.min_init_features >= 10, source, "tracking.min_init_features must be >= 10");
  require(t.min_tracked_inliers >= 6, source, "tracking.min_tracked_inliers must be >= 6");
  require(t.max_frames_between_keyframes >= 0, source, "tracking.max_frames_between_keyframes must be >= 0");
  require(t.relocalization_attempts >= 0, source, "tracking.relocalization_attempts must be >= 0");
  require(t.relocalization_candidates >= 0, source,
          "tracking.relocalization_candidates must be >= 0 (0 = every keyframe)");
  require(t.max_predicted_frames >= 0 && t.max_predicted_frames <= 30, source,
          "tracking.max_predicted_frames must be in [0, 30]");
  require(t.blur_ratio >= 0 && t.blur_ratio < 1, source, "tracking.blur_ratio must be in [0, 1)");
  require(t.max_jump_deg >= 0 && t.max_jump_m >= 0, source,
          "tracking.max_jump_deg and max_jump_m must be >= 0 (0 = off)");
  require(t.covered_ratio > 0, source, "tracking.covered_ratio must be > 0 (> 1 = off)");
  require(t.min_rescued_inliers >= 0, source, "tracking.min_rescued_inliers must be >= 0 (0 = off)");
  require(t.pose_check_m >= 0, source, "tracking.pose_check_m must be >= 0 (0 = off)");
  require(t.excursion_m >= 0, source, "tracking.excursion_m must be >= 0 (0 = off)");
}

void checkMapping(const MappingParams& m, const std::string& source) {
  require(m.local_ba_iterations >= 0, source, "mapping.local_ba_iterations must be >= 0");
  require(m.covisible_keyframes >= 1, source, "mapping.covisible_keyframes must be >= 1");
  require(m.keyframe_redundancy > 0 && m.keyframe_redundancy <= 1, source,
          "mapping.keyframe_redundancy must be in (0, 1]");
  require(m.max_keyframe_shift_m >= 0 && m.max_keyframe_shift_deg >= 0, source,
          "mapping.max_keyframe_shift_m and max_keyframe_shift_deg must be >= 0 (0 = off)");
}

void checkLoop(const LoopParams& l, const std::string& source) {
  require(l.min_inliers >= 10, source, "loop.min_inliers must be >= 10");
  require(l.confirm_within >= 1, source, "loop.confirm_within must be >= 1 (1 = the next keyframe only)");
  require(l.min_keyframe_gap >= 1, source, "loop.min_keyframe_gap must be >= 1");
  require(l.candidates >= 1, source, "loop.candidates must be >= 1");
  require(l.word_candidates >= 0, source, "loop.word_candidates must be >= 0 (0 = every candidate)");
  require(l.min_correction_m >= 0, source, "loop.min_correction_m must be >= 0");
  require(l.min_correction_deg >= 0, source, "loop.min_correction_deg must be >= 0");
  require(l.global_ba_iterations >= 0, source, "loop.global_ba_iterations must be >= 0");
}

/// The object mask's options (dynamic.object_*).
void checkObjectMask(const DynamicParams& d, const std::string& source) {
  const auto& o = d.object;
  require(o.behind >= 0, source, "dynamic.object_behind must be >= 0 (m)");
  require(o.behind_per_size >= 0, source, "dynamic.object_behind_per_size must be >= 0");
  require(!o.colour || d.object_mask, source,
          "dynamic.object_colour needs dynamic.object_mask: true (it refines the object mask)");
  require(!o.region || d.object_mask, source,
          "dynamic.object_region needs dynamic.object_mask: true (it refines the object mask)");
  require(!(o.region && o.colour), source,
          "dynamic.object_region and dynamic.object_colour are two ways to segment the object: choose one");
  require(o.region_step > 0 && o.region_step <= 1, source,
          "dynamic.object_region_step must be in (0, 1] (a share of the depth)");
  require(o.radius >= 0 && o.radius <= 64, source, "dynamic.object_radius must be in [0, 64] px");
}

/// The multi-view-geometry check's options (ratio threshold, references, occlusion, unboxed check).
void checkGeometry(const dynamic::GeometryParams& g, const std::string& source) {
  require(g.ratio_threshold >= 0 && g.ratio_threshold <= 1, source, "dynamic.ratio_threshold must be in [0, 1]");
  require(g.reference_keyframes >= 1, source, "dynamic.reference_keyframes must be >= 1");
  require(g.reference_max_depth > 0 && g.current_max_depth > 0, source,
          "dynamic.reference_max_depth and current_max_depth must be > 0 (m)");
  require(g.occlusion_threshold > 0, source, "dynamic.occlusion_threshold must be > 0");
  require(g.patch_radius >= 0 && g.patch_radius <= 20, source, "dynamic.patch_radius must be in [0, 20]");
  require(g.max_patch_std > 0, source, "dynamic.max_patch_std must be > 0 (m)");
  require(g.region_depth_step > 0, source, "dynamic.region_depth_step must be > 0");
  require(g.max_parallax_deg > 0 && g.max_parallax_deg <= 180, source, "dynamic.max_parallax_deg must be in (0, 180]");
  require(g.occluder_radius >= 0 && g.occluder_radius <= 64, source, "dynamic.occluder_radius must be in [0, 64] px");
  require(g.occluder_depth >= 0, source, "dynamic.occluder_depth must be >= 0 (m)");
  require(g.unboxed_min_evidence >= 1, source, "dynamic.unboxed_min_evidence must be >= 1");
  require(g.unboxed_depth_range > 0, source, "dynamic.unboxed_depth_range must be > 0");
  require(g.unboxed_min_hidden >= 0 && g.unboxed_min_hidden <= 1, source,
          "dynamic.unboxed_min_hidden must be in [0, 1]");
}

void checkDynamic(const DynamicParams& d, const std::string& source) {
  require(d.box_flow == "auto" || d.box_flow == "on" || d.box_flow == "off", source,
          "dynamic.box_flow must be auto, on or off");
  require(d.detect_every >= 1, source, "dynamic.detect_every must be >= 1");
  require(d.box_margin >= 0 && d.box_margin <= 0.5, source, "dynamic.box_margin must be in [0, 0.5]");
  require(d.refill_ratio >= 0 && d.refill_ratio <= 1, source, "dynamic.refill_ratio must be in [0, 1]");
  require(d.detector_tiles >= 1 && d.detector_tiles <= 9, source, "dynamic.detector_tiles must be in [1, 9]");
  require(d.detector_tiles == 1 || d.lookahead, source,
          "dynamic.detector_tiles > 1 needs dynamic.lookahead: true (the tiles are frames still to be tracked)");
  require(d.detector_latency >= 0 && d.detector_latency <= d.detect_every * d.detector_tiles, source,
          "dynamic.detector_latency must be in [0, detect_every x detector_tiles]");
  const auto& t = d.tracker;
  require(t.kalman.q > 0 && t.kalman.r > 0, source, "dynamic.kalman_q and kalman_r must be > 0");
  require(t.iou_gate >= 0 && t.iou_gate < 1, source, "dynamic.iou_gate must be in [0, 1)");
  require(t.centre_gate >= 0 && t.centre_gate_max >= 0, source, "dynamic.centre_gate and centre_gate_max must be >= 0");
  require(t.max_age >= 0, source, "dynamic.max_age must be >= 0");
  checkObjectMask(d, source);
  checkGeometry(d.geometry, source);
}

// Reading one key: most types as they are; the distortion as a list of 4 or 5, the mode by name.
template <typename T>
void readKey(Section& s, const std::string& key, T& value, bool required) {
  s.get(key, value, required);
}

void readKey(Section& s, const std::string& key, std::array<double, 5>& value, bool required) {
  std::vector<double> list;
  s.get(key, list, required);
  if (list.empty()) return;
  s.require(list.size() == 4 || list.size() == 5, "camera.distortion must list 4 or 5 coefficients: k1 k2 p1 p2 [k3]");
  value.fill(0.0);
  std::copy(list.begin(), list.end(), value.begin());
}

void readKey(Section& s, const std::string& key, DynamicMode& value, bool required) {
  std::string name = toString(value);
  s.get(key, name, required);
  try {
    value = parseDynamicMode(name);
  } catch (const InputError& e) {
    s.require(false, fmt::format("dynamic.mode: {}", e.what()));
  }
}

// Writing one key: doubles in their shortest exact form, so the file reads back bit-identical.
template <typename T>
void writeValue(YAML::Emitter& out, const T& value) {
  if constexpr (std::is_floating_point_v<T>) {
    out << fmt::format("{}", value);
  } else {
    out << value;
  }
}

template <typename T, size_t N>
void writeValue(YAML::Emitter& out, const std::array<T, N>& values) {
  out << YAML::Flow << YAML::BeginSeq;
  for (const auto& v : values) writeValue(out, v);
  out << YAML::EndSeq;
}

void writeValue(YAML::Emitter& out, const std::vector<int>& values) {
  out << YAML::Flow << YAML::BeginSeq;
  for (int v : values) out << v;
  out << YAML::EndSeq;
}

void writeValue(YAML::Emitter& out, DynamicMode mode) { out << toString(mode); }

// Applies "section.key=value" overrides to the parsed file; returns the keys set, by section. (An unknown
// key in a known section is left to Section::checkNoUnknownKeys, like the file's own.)
std::map<std::string, Overridden> applyOverrides(YAML::Node& root, const std::vector<std::string>& overrides,
                                                 const std::string& source) {
  std::map<std::string, Overridden> overridden;
  for (const auto& o : overrides) {
    const size_t eq = o.find('='), dot = o.find('.');
    if (eq == std::string::npos || dot == std::string::npos || dot == 0 || dot + 1 >= eq) {
      throw InputError(fmt::format("--set '{}': expected section.key=value, e.g. dynamic.max_age=5", o));
    }
    const std::string section = o.substr(0, dot), key = o.substr(dot + 1, eq - dot - 1), text = o.substr(eq + 1);
    if (std::find(kSections.begin(), kSections.end(), section) == kSections.end()) {
      throw InputError(unknownOverride(o, section, key));
    }
    YAML::Node value;
    try {
      value = YAML::Load(text);
    } catch (const YAML::Exception& e) {
      throw InputError(fmt::format("--set '{}': the value is not valid YAML: {}", o, e.msg));
    }
    if (!value || value.IsNull()) throw InputError(fmt::format("--set '{}': no value after '='", o));
    YAML::Node in_file = root[section];
    if (!in_file || in_file.IsNull()) {
      root[section] = YAML::Node(YAML::NodeType::Map);
    } else if (!in_file.IsMap()) {
      throw InputError(fmt::format("{}: section '{}' must be a mapping", source, section));
    }
    root[section][key] = value;
    overridden[section][key] = o;  // the last of one key's overrides wins, in the file and in messages
  }
  return overridden;
}

}  // namespace

SlamConfig parseConfig(const std::string& yaml_text, const std::string& source,
                       const std::vector<std::string>& overrides) {
  YAML::Node root;
  try {
    root = YAML::Load(yaml_text);
  } catch (const YAML::Exception& e) {
    throw InputError(fmt::format("{}: not valid YAML (line {}): {}", source, e.mark.line + 1, e.msg));
  }
  if (!root.IsMap()) throw InputError(fmt::format("{}: expected a YAML mapping at top level", source));
  checkNoDuplicateKeys(root, source, "", "the top level");
  for (const auto& kv : root) {
    const auto key = keyName(kv.first, source, "the top level");
    if (std::find(kSections.begin(), kSections.end(), key) == kSections.end()) {
      throw InputError(fmt::format("{}: unknown section '{}'", source, key));
    }
  }
  const auto overridden = applyOverrides(root, overrides, source);
  // Range checks name the overrides too: the value may have come from either.
  std::string checked = source;
  for (const auto& o : overrides) checked += " --set " + o;
  std::map<std::string, Section> sections;
  for (const auto& name : kSections) {
    const auto o = overridden.find(name);
    sections.try_emplace(name, root, name, source, name == "camera",
                         o == overridden.end() ? Overridden{} : o->second, checked);
  }

  SlamConfig c;
  c.source = source;
  forEachKey(c, [&](const char* section, const char* key, auto& field, bool required) {
    readKey(sections.at(section), key, field, required);
  });
  for (const auto& [name, s] : sections) s.checkNoUnknownKeys();

  checkCameraDepthOrb(c, checked);
  checkTracking(c.tracking, checked);
  checkMapping(c.mapping, checked);
  checkLoop(c.loop, checked);
  // A relative model path is relative to the config file's folder.
  auto& model = c.dynamic.detector.model;
  if (!model.empty() && std::filesystem::path(model).is_relative()) {
    model = (std::filesystem::path(source).parent_path() / model).lexically_normal().string();
  }
  c.dynamic.object.focal_px = c.camera.fy;  // box sizes (px) to metres
  checkDynamic(c.dynamic, checked);
  require(c.opencv_threads >= 0 && c.opencv_threads <= SlamConfig::kMaxOpenCvThreads, checked,
          fmt::format("system.opencv_threads must be in [0, {}] (0 = OpenCV's default)", SlamConfig::kMaxOpenCvThreads));

  return c;
}

std::string configToYaml(const SlamConfig& config) {
  YAML::Emitter out;
  out << YAML::BeginMap;
  std::string open;  // the section being written
  forEachKey(config, [&](const char* section, const char* key, const auto& value, bool) {
    if (open != section) {
      if (!open.empty()) out << YAML::EndMap;
      out << YAML::Key << section << YAML::Value << YAML::BeginMap;
      open = section;
    }
    out << YAML::Key << key << YAML::Value;
    writeValue(out, value);
  });
  out << YAML::EndMap << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

SlamConfig loadConfig(const std::string& path, const std::vector<std::string>& overrides) {
  std::ifstream in = openInputFile(path, "config file");
  std::stringstream ss;
  ss << in.rdbuf();
  return parseConfig(ss.str(), path, overrides);
}

}  // namespace tkgslam::io
