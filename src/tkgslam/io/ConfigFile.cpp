#include "tkgslam/io/ConfigFile.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <type_traits>
#include <set>
#include <sstream>

#include <fmt/format.h>
#include <yaml-cpp/yaml.h>

#include "tkgslam/common/Error.h"

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

// Reads one mapping section, remembering which keys were used so leftovers can be reported.
class Section {
 public:
  Section(const YAML::Node& root, std::string name, std::string source, bool required)
      : name_(std::move(name)), source_(std::move(source)) {
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
      throw InputError(fmt::format("{}: key '{}.{}' has an invalid value", source_, name_, key));
    }
    // .nan/.inf parse as doubles but would pass or poison every later range check.
    if (!isFinite(parsed)) throw InputError(fmt::format("{}: key '{}.{}' must be finite", source_, name_, key));
    value = std::move(parsed);
  }

  void checkNoUnknownKeys() const {
    if (!present_) return;
    for (const auto& kv : node_) {
      const auto key = keyName(kv.first, source_, "section '" + name_ + "'");
      if (!used_.count(key)) throw InputError(fmt::format("{}: unknown key '{}.{}'", source_, name_, key));
    }
  }

 private:
  YAML::Node node_;
  bool present_ = false;
  std::string name_, source_;
  std::set<std::string> used_;
};

void require(bool ok, const std::string& source, const std::string& what) {
  if (!ok) throw InputError(fmt::format("{}: {}", source, what));
}

}  // namespace

SlamConfig parseConfig(const std::string& yaml_text, const std::string& source) {
  YAML::Node root;
  try {
    root = YAML::Load(yaml_text);
  } catch (const YAML::Exception& e) {
    throw InputError(fmt::format("{}: not valid YAML (line {}): {}", source, e.mark.line + 1, e.msg));
  }
  if (!root.IsMap()) throw InputError(fmt::format("{}: expected a YAML mapping at top level", source));
  checkNoDuplicateKeys(root, source, "", "the top level");
  static const std::set<std::string> kSections = {"camera", "depth", "orb", "tracking", "mapping", "loop", "dynamic", "system"};
  for (const auto& kv : root) {
    const auto key = keyName(kv.first, source, "the top level");
    if (!kSections.count(key)) throw InputError(fmt::format("{}: unknown section '{}'", source, key));
  }

  SlamConfig c;
  c.source = source;
  {
    Section s(root, "camera", source, true);
    s.get("width", c.camera.width, true);
    s.get("height", c.camera.height, true);
    s.get("fx", c.camera.fx, true);
    s.get("fy", c.camera.fy, true);
    s.get("cx", c.camera.cx, true);
    s.get("cy", c.camera.cy, true);
    std::vector<double> dist;
    s.get("distortion", dist);
    require(dist.empty() || dist.size() == 4 || dist.size() == 5, source,
            "camera.distortion must list 4 or 5 coefficients: k1 k2 p1 p2 [k3]");
    for (size_t i = 0; i < dist.size(); ++i) c.camera.distortion[i] = dist[i];
    s.get("fps", c.camera.fps);
    s.checkNoUnknownKeys();
    try {
      camera::PinholeCamera check(c.camera);
    } catch (const InputError& e) {
      throw InputError(fmt::format("{}: {}", source, e.what()));
    }
  }
  {
    Section s(root, "depth", source, false);
    s.get("factor", c.depth.factor);
    s.get("baseline_fx", c.depth.baseline_fx);
    s.get("close_threshold", c.depth.close_threshold);
    s.get("max_depth", c.depth.max_depth);
    s.checkNoUnknownKeys();
    require(c.depth.factor > 0, source, "depth.factor must be > 0");
    require(c.depth.baseline_fx > 0, source, "depth.baseline_fx must be > 0");
    require(c.depth.close_threshold > 0, source, "depth.close_threshold must be > 0");
    require(c.depth.max_depth > 0, source, "depth.max_depth must be > 0");
  }
  {
    Section s(root, "orb", source, false);
    s.get("features", c.orb.features);
    s.get("scale_factor", c.orb.scale_factor);
    s.get("levels", c.orb.levels);
    s.get("fast_threshold", c.orb.fast_threshold);
    s.get("fast_min_threshold", c.orb.fast_min_threshold);
    s.checkNoUnknownKeys();
    try {
      feature::OrbExtractor check(c.orb);
    } catch (const InputError& e) {
      throw InputError(fmt::format("{}: {}", source, e.what()));
    }
  }
  {
    Section s(root, "tracking", source, false);
    s.get("min_init_features", c.tracking.min_init_features);
    s.get("min_tracked_inliers", c.tracking.min_tracked_inliers);
    s.get("max_frames_between_keyframes", c.tracking.max_frames_between_keyframes);
    s.get("relocalization_attempts", c.tracking.relocalization_attempts);
    s.get("max_predicted_frames", c.tracking.max_predicted_frames);
    s.get("reanchor_segments", c.tracking.reanchor_segments);
    s.get("blur_ratio", c.tracking.blur_ratio);
    s.get("max_jump_deg", c.tracking.max_jump_deg);
    s.get("max_jump_m", c.tracking.max_jump_m);
    s.get("covered_ratio", c.tracking.covered_ratio);
    s.get("min_rescued_inliers", c.tracking.min_rescued_inliers);
    s.checkNoUnknownKeys();
    require(c.tracking.min_init_features >= 10, source, "tracking.min_init_features must be >= 10");
    require(c.tracking.min_tracked_inliers >= 6, source, "tracking.min_tracked_inliers must be >= 6");
    require(c.tracking.max_frames_between_keyframes >= 0, source,
            "tracking.max_frames_between_keyframes must be >= 0");
    require(c.tracking.relocalization_attempts >= 0, source, "tracking.relocalization_attempts must be >= 0");
    require(c.tracking.max_predicted_frames >= 0 && c.tracking.max_predicted_frames <= 30, source,
            "tracking.max_predicted_frames must be in [0, 30]");
    require(c.tracking.blur_ratio >= 0 && c.tracking.blur_ratio < 1, source, "tracking.blur_ratio must be in [0, 1)");
    require(c.tracking.covered_ratio > 0, source, "tracking.covered_ratio must be > 0 (> 1 = off)");
    require(c.tracking.min_rescued_inliers >= 0, source, "tracking.min_rescued_inliers must be >= 0 (0 = off)");
  }
  {
    Section s(root, "mapping", source, false);
    s.get("local_ba_iterations", c.mapping.local_ba_iterations);
    s.get("covisible_keyframes", c.mapping.covisible_keyframes);
    s.get("keyframe_redundancy", c.mapping.keyframe_redundancy);
    s.get("max_keyframe_shift_m", c.mapping.max_keyframe_shift_m);
    s.get("max_keyframe_shift_deg", c.mapping.max_keyframe_shift_deg);
    s.get("cull_keyframes", c.mapping.cull_keyframes);
    s.checkNoUnknownKeys();
    require(c.mapping.local_ba_iterations >= 0, source, "mapping.local_ba_iterations must be >= 0");
    require(c.mapping.covisible_keyframes >= 1, source, "mapping.covisible_keyframes must be >= 1");
    require(c.mapping.keyframe_redundancy > 0 && c.mapping.keyframe_redundancy <= 1, source,
            "mapping.keyframe_redundancy must be in (0, 1]");
  }
  {
    Section s(root, "loop", source, false);
    s.get("enabled", c.loop.enabled);
    s.get("confirm", c.loop.confirm);
    s.get("min_inliers", c.loop.min_inliers);
    s.get("min_keyframe_gap", c.loop.min_keyframe_gap);
    s.get("candidates", c.loop.candidates);
    s.get("min_correction_m", c.loop.min_correction_m);
    s.get("min_correction_deg", c.loop.min_correction_deg);
    s.get("global_ba_iterations", c.loop.global_ba_iterations);
    s.checkNoUnknownKeys();
    require(c.loop.min_inliers >= 10, source, "loop.min_inliers must be >= 10");
    require(c.loop.min_keyframe_gap >= 1, source, "loop.min_keyframe_gap must be >= 1");
    require(c.loop.candidates >= 1, source, "loop.candidates must be >= 1");
    require(c.loop.min_correction_m >= 0, source, "loop.min_correction_m must be >= 0");
    require(c.loop.min_correction_deg >= 0, source, "loop.min_correction_deg must be >= 0");
    require(c.loop.global_ba_iterations >= 0, source, "loop.global_ba_iterations must be >= 0");
  }
  {
    Section s(root, "dynamic", source, false);
    std::string mode = toString(c.dynamic.mode);
    s.get("mode", mode);
    try {
      c.dynamic.mode = parseDynamicMode(mode);
    } catch (const InputError& e) {
      throw InputError(fmt::format("{}: dynamic.mode: {}", source, e.what()));
    }
    auto& d = c.dynamic.detector;
    s.get("model", d.model);
    s.get("input_size", d.input_size);
    s.get("confidence", d.confidence);
    s.get("person_confidence", d.person_confidence);
    s.get("nms", d.nms);
    s.get("classes", d.classes);
    s.get("detect_every", c.dynamic.detect_every);
    s.get("detector_latency", c.dynamic.detector_latency);
    s.get("box_margin", c.dynamic.box_margin);
    s.get("object_mask", c.dynamic.object_mask);
    s.get("object_behind", c.dynamic.object.behind);
    s.get("object_behind_per_size", c.dynamic.object.behind_per_size);
    c.dynamic.object.focal_px = c.camera.fy;  // box sizes (px) to metres
    s.get("object_radius", c.dynamic.object.radius);
    s.get("object_colour", c.dynamic.object.colour);
    s.get("box_flow", c.dynamic.box_flow);
    s.get("lookahead", c.dynamic.lookahead);
    s.get("detector_tiles", c.dynamic.detector_tiles);
    s.get("refill_ratio", c.dynamic.refill_ratio);
    s.get("late_culling", c.dynamic.late_culling);
    auto& t = c.dynamic.tracker;
    s.get("kalman_q", t.kalman.q);
    s.get("kalman_r", t.kalman.r);
    s.get("iou_gate", t.iou_gate);
    s.get("centre_gate", t.centre_gate);
    s.get("centre_gate_max", t.centre_gate_max);
    s.get("max_age", t.max_age);
    auto& g = c.dynamic.geometry;
    s.get("ratio_threshold", g.ratio_threshold);
    s.get("reference_keyframes", g.reference_keyframes);
    s.get("reference_max_depth", g.reference_max_depth);
    s.get("current_max_depth", g.current_max_depth);
    s.get("max_parallax_deg", g.max_parallax_deg);
    s.get("occlusion_threshold", g.occlusion_threshold);
    s.get("patch_radius", g.patch_radius);
    s.get("max_patch_std", g.max_patch_std);
    s.get("region_depth_step", g.region_depth_step);
    s.get("occluder_radius", g.occluder_radius);
    s.get("occluder_depth", g.occluder_depth);
    s.get("unboxed_check", g.unboxed_check);
    s.get("unboxed_min_evidence", g.unboxed_min_evidence);
    s.get("unboxed_depth_range", g.unboxed_depth_range);
    s.get("unboxed_min_hidden", g.unboxed_min_hidden);
    s.checkNoUnknownKeys();
    // A relative model path is relative to the config file's folder.
    if (!d.model.empty() && std::filesystem::path(d.model).is_relative()) {
      d.model = (std::filesystem::path(source).parent_path() / d.model).lexically_normal().string();
    }
    require(c.dynamic.box_flow == "auto" || c.dynamic.box_flow == "on" || c.dynamic.box_flow == "off", source,
            "dynamic.box_flow must be auto, on or off");
    require(c.dynamic.detect_every >= 1, source, "dynamic.detect_every must be >= 1");
    require(g.occluder_radius >= 0 && g.occluder_radius <= 64, source, "dynamic.occluder_radius must be in [0, 64] px");
    require(g.occluder_depth >= 0, source, "dynamic.occluder_depth must be >= 0 (m)");
    require(g.unboxed_min_evidence >= 1, source, "dynamic.unboxed_min_evidence must be >= 1");
    require(g.unboxed_depth_range > 0, source, "dynamic.unboxed_depth_range must be > 0");
    require(g.unboxed_min_hidden >= 0 && g.unboxed_min_hidden <= 1, source,
            "dynamic.unboxed_min_hidden must be in [0, 1]");
    require(c.dynamic.box_margin >= 0 && c.dynamic.box_margin <= 0.5, source, "dynamic.box_margin must be in [0, 0.5]");
    require(c.dynamic.object.behind >= 0, source, "dynamic.object_behind must be >= 0 (m)");
    require(c.dynamic.object.behind_per_size >= 0, source, "dynamic.object_behind_per_size must be >= 0");
    require(!c.dynamic.object.colour || c.dynamic.object_mask, source,
            "dynamic.object_colour needs dynamic.object_mask: true (it refines the object mask)");
    require(c.dynamic.object.radius >= 0 && c.dynamic.object.radius <= 64, source,
            "dynamic.object_radius must be in [0, 64] px");
    require(c.dynamic.refill_ratio >= 0 && c.dynamic.refill_ratio <= 1, source, "dynamic.refill_ratio must be in [0, 1]");
    require(c.dynamic.detector_tiles >= 1 && c.dynamic.detector_tiles <= 9, source,
            "dynamic.detector_tiles must be in [1, 9]");
    require(c.dynamic.detector_tiles == 1 || c.dynamic.lookahead, source,
            "dynamic.detector_tiles > 1 needs dynamic.lookahead: true (the tiles are frames still to be tracked)");
    require(c.dynamic.detector_latency >= 0 &&
                c.dynamic.detector_latency <= c.dynamic.detect_every * c.dynamic.detector_tiles,
            source, "dynamic.detector_latency must be in [0, detect_every x detector_tiles]");
    require(t.kalman.q > 0 && t.kalman.r > 0, source, "dynamic.kalman_q and kalman_r must be > 0");
    require(t.iou_gate >= 0 && t.iou_gate < 1, source, "dynamic.iou_gate must be in [0, 1)");
    require(t.centre_gate >= 0 && t.centre_gate_max >= 0, source, "dynamic.centre_gate and centre_gate_max must be >= 0");
    require(t.max_age >= 0, source, "dynamic.max_age must be >= 0");
    require(g.ratio_threshold >= 0 && g.ratio_threshold <= 1, source, "dynamic.ratio_threshold must be in [0, 1]");
    require(g.reference_keyframes >= 1, source, "dynamic.reference_keyframes must be >= 1");
    require(g.occlusion_threshold > 0, source, "dynamic.occlusion_threshold must be > 0");
    require(g.patch_radius >= 0 && g.patch_radius <= 20, source, "dynamic.patch_radius must be in [0, 20]");
    require(g.region_depth_step > 0, source, "dynamic.region_depth_step must be > 0");
    require(g.max_parallax_deg > 0 && g.max_parallax_deg <= 180, source, "dynamic.max_parallax_deg must be in (0, 180]");
  }
  {
    Section s(root, "system", source, false);
    s.get("deterministic", c.deterministic);
    s.get("seed", c.seed);
    s.get("opencv_threads", c.opencv_threads);
    s.checkNoUnknownKeys();
    require(c.opencv_threads >= 0, source, "system.opencv_threads must be >= 0");
  }
  return c;
}

SlamConfig loadConfig(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(fmt::format("cannot open config file '{}'", path));
  std::stringstream ss;
  ss << in.rdbuf();
  return parseConfig(ss.str(), path);
}

}  // namespace tkgslam::io
