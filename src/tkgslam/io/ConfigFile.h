#pragma once
// YAML configuration. Every section and key is optional except camera intrinsics and size;
// unknown keys are errors (a typo must not silently fall back to a default).
//
//   camera:  { width, height, fx, fy, cx, cy, distortion: [k1, k2, p1, p2, k3], fps }
//   depth:   { factor (raw units per metre), baseline_fx (virtual stereo baseline * fx, m*px),
//              close_threshold (m), max_depth (m) }
//   orb:     { features, scale_factor, levels, fast_threshold, fast_min_threshold }
//   system:  { deterministic, seed, opencv_threads }
// and tracking, mapping, loop, dynamic: every key is listed once, in forEachKey (ConfigFile.cpp), and
// documented in the README's "Camera config format".
#include <string>
#include <vector>

#include "tkgslam/system/SlamConfig.h"

namespace tkgslam::io {

/// Loads and validates a config file. Throws InputError naming the file and key on any problem.
/// `overrides` ("section.key=value", the value in YAML: `dynamic.max_age=5`, `camera.distortion=[0,0,0,0]`)
/// replace or add keys before the file is read, so they are checked like the file's own keys; an
/// unknown key or a value of the wrong kind names the override.
SlamConfig loadConfig(const std::string& path, const std::vector<std::string>& overrides = {});

/// Parses a config from YAML text (`source` names it in error messages), with `overrides` as above.
SlamConfig parseConfig(const std::string& yaml_text, const std::string& source,
                       const std::vector<std::string>& overrides = {});

/// Every key of `config` as YAML that parseConfig reads back to the same values, bit for bit (the
/// model path as it is in `config`: parseConfig resolves a relative one against the file's folder).
std::string configToYaml(const SlamConfig& config);

}  // namespace tkgslam::io
