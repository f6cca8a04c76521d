#include <gtest/gtest.h>

#include "TestSupport.h"
#include "tkgslam/common/Error.h"
#include "tkgslam/io/ConfigFile.h"

namespace tkgslam {
namespace {

const char* kMinimal = "camera: {width: 640, height: 480, fx: 500, fy: 500, cx: 320, cy: 240}\n";

std::string errorOf(const std::string& yaml) {
  try {
    io::parseConfig(yaml, "cfg.yaml");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(ConfigFile, BundledConfigsLoad) {
  for (const char* name : {"tum_fr1.yaml", "tum_fr2.yaml", "tum_fr3.yaml"}) {
    const auto c = io::loadConfig((test::sourceDir() / "configs" / name).string());
    EXPECT_EQ(c.camera.width, 640) << name;
    EXPECT_GT(c.camera.fx, 500) << name;
    EXPECT_EQ(c.orb.features, 1000) << name;
  }
  const auto fr1 = io::loadConfig((test::sourceDir() / "configs" / "tum_fr1.yaml").string());
  EXPECT_DOUBLE_EQ(fr1.camera.distortion[4], 1.163314);
  EXPECT_DOUBLE_EQ(fr1.depth.factor, 5000);
}

TEST(ConfigFile, WrittenOutItReadsBackToTheSameValuesBitForBit) {
  for (const char* name : {"tum_fr1.yaml", "tum_fr2.yaml", "tum_fr3.yaml"}) {
    auto c = io::loadConfig((test::sourceDir() / "configs" / name).string());
    // Values the shortest decimal form must keep exact, and non-defaults of every kind.
    c.tracking.max_jump_m = 0.1 + 0.2;  // 0.30000000000000004
    c.dynamic.geometry.occlusion_threshold = 1.0 / 3.0;
    c.dynamic.mode = DynamicMode::TG;
    c.dynamic.detector.classes = {0, 16};
    c.dynamic.box_flow = "off";
    c.mapping.cull_keyframes = false;
    c.seed = 18446744073709551615ull;
    const std::string yaml = io::configToYaml(c);
    const auto back = io::parseConfig(yaml, c.source);
    EXPECT_EQ(io::configToYaml(back), yaml) << name;
    EXPECT_EQ(back.tracking.max_jump_m, 0.1 + 0.2) << name;
    EXPECT_EQ(back.dynamic.geometry.occlusion_threshold, 1.0 / 3.0) << name;
    EXPECT_EQ(back.camera.distortion, c.camera.distortion) << name;
    EXPECT_EQ(back.camera.fx, c.camera.fx) << name;
    EXPECT_EQ(back.dynamic.mode, DynamicMode::TG) << name;
    EXPECT_EQ(back.dynamic.detector.classes, (std::vector<int>{0, 16})) << name;
    EXPECT_EQ(back.dynamic.box_flow, "off") << name;
    EXPECT_FALSE(back.mapping.cull_keyframes) << name;
    EXPECT_EQ(back.seed, c.seed) << name;
    EXPECT_EQ(back.dynamic.detector.model, c.dynamic.detector.model) << name;  // absolute after loadConfig
    // Every section, each once.
    for (const char* section : {"camera:", "depth:", "orb:", "tracking:", "mapping:", "loop:", "dynamic:", "system:"}) {
      EXPECT_NE(("\n" + yaml).find(std::string("\n") + section + "\n"), std::string::npos) << section;
    }
  }
}

std::string overrideErrorOf(const std::string& yaml, const std::vector<std::string>& overrides) {
  try {
    io::parseConfig(yaml, "cfg.yaml", overrides);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

TEST(ConfigFile, CommandLineOverridesReplaceAndAddKeysAndAreCheckedLikeTheFilesOwn) {
  const std::string yaml = std::string(kMinimal) + "dynamic: {max_age: 3, mode: TKG}\n";
  const auto c = io::parseConfig(yaml, "cfg.yaml",
                                 {"dynamic.max_age=7", "loop.min_inliers=33", "camera.distortion=[0.1, 0, 0, 0]",
                                  "tracking.max_jump_m=0.05", "camera.fx=510.5"});
  EXPECT_EQ(c.dynamic.tracker.max_age, 7);              // replaced
  EXPECT_EQ(c.dynamic.mode, DynamicMode::TKG);  // the rest of the section kept
  EXPECT_EQ(c.loop.min_inliers, 33);            // a section the file does not have
  EXPECT_DOUBLE_EQ(c.camera.distortion[0], 0.1);
  EXPECT_DOUBLE_EQ(c.tracking.max_jump_m, 0.05);
  EXPECT_DOUBLE_EQ(c.camera.fx, 510.5);
  // The last of one key's overrides wins.
  EXPECT_EQ(io::parseConfig(yaml, "cfg.yaml", {"dynamic.max_age=2", "dynamic.max_age=5"}).dynamic.tracker.max_age, 5);
  // Errors name the override, not the file.
  EXPECT_NE(overrideErrorOf(yaml, {"dynamic.max_agee=5"})
                .find("--set 'dynamic.max_agee=5': unknown key 'dynamic.max_agee'"),
            std::string::npos);
  EXPECT_NE(overrideErrorOf(yaml, {"dinamic.max_age=5"}).find("unknown key 'dinamic.max_age'"), std::string::npos);
  EXPECT_NE(overrideErrorOf(yaml, {"dynamic.max_age=abc"}).find("--set dynamic.max_age=abc: invalid value, it takes"),
            std::string::npos);
  EXPECT_NE(overrideErrorOf(yaml, {"dynamic.max_age=-1"})
                .find("cfg.yaml --set dynamic.max_age=-1: dynamic.max_age must be >= 0"),
            std::string::npos);
  EXPECT_NE(overrideErrorOf(yaml, {"camera.distortion=[0.1, 0.2]"})
                .find("cfg.yaml --set camera.distortion=[0.1, 0.2]: camera.distortion must list 4 or 5"),
            std::string::npos);
  for (const char* malformed : {"max_age=5", "dynamic.max_age", ".max_age=5", "dynamic.=5", "dynamic=5"}) {
    EXPECT_NE(overrideErrorOf(yaml, {malformed}).find("expected section.key=value"), std::string::npos) << malformed;
  }
  EXPECT_NE(overrideErrorOf(yaml, {"dynamic.max_age="}).find("no value after '='"), std::string::npos);
  EXPECT_NE(overrideErrorOf(yaml, {"dynamic.max_age=[1"}).find("not valid YAML"), std::string::npos);
  // A file whose section is not a mapping stays an error of the file.
  EXPECT_NE(overrideErrorOf(std::string(kMinimal) + "loop: 5\n", {"loop.min_inliers=33"})
                .find("cfg.yaml: section 'loop' must be a mapping"),
            std::string::npos);
}

TEST(ConfigFile, MinimalConfigGetsDefaults) {
  const auto c = io::parseConfig(kMinimal, "x");
  EXPECT_DOUBLE_EQ(c.depth.factor, 5000);
  EXPECT_EQ(c.orb.levels, 8);
}

TEST(ConfigFile, LookaheadOnlyWhereThereIsSomethingToLookAheadTo) {
  const auto base = std::string(kMinimal) + "dynamic: {lookahead: true, ";
  EXPECT_FALSE(io::parseConfig(kMinimal, "x").dynamic.usesLookahead());  // off by default
  EXPECT_TRUE(io::parseConfig(base + "mode: TKG, detect_every: 8, detector_latency: 8}", "x").dynamic.usesLookahead());
  EXPECT_TRUE(io::parseConfig(base + "mode: TK, detect_every: 4}", "x").dynamic.usesLookahead());
  // Detection on every frame, or no Kalman tracker to carry the boxes: nothing to hold frames for.
  EXPECT_FALSE(io::parseConfig(base + "mode: TKG}", "x").dynamic.usesLookahead());
  EXPECT_FALSE(io::parseConfig(base + "mode: T, detect_every: 8, detector_latency: 8}", "x").dynamic.usesLookahead());
  EXPECT_NE(errorOf(base + "mode: TKG, detect_every: 8, lookahed: 1}").find("lookahed"), std::string::npos);
  // Tiled detector runs: the latency may reach a whole run period (detect_every x tiles).
  const auto tiled = io::parseConfig(base + "mode: TKG, detect_every: 2, detector_latency: 8, detector_tiles: 4}", "x");
  EXPECT_TRUE(tiled.dynamic.usesLookahead());
  EXPECT_EQ(tiled.dynamic.usesTiles(), 4);
  EXPECT_TRUE(io::parseConfig(base + "mode: TKG, detector_tiles: 4}", "x").dynamic.usesLookahead());
  EXPECT_EQ(io::parseConfig(base + "mode: T, detector_tiles: 4}", "x").dynamic.usesTiles(), 1);  // no Kalman
  EXPECT_NE(errorOf(base + "mode: TKG, detect_every: 2, detector_latency: 9, detector_tiles: 4}").find("detect_every x detector_tiles"),
            std::string::npos);
  EXPECT_NE(errorOf(std::string(kMinimal) + "dynamic: {mode: TKG, detector_tiles: 4}").find("needs dynamic.lookahead"),
            std::string::npos);
  EXPECT_NE(errorOf(base + "mode: TKG, detector_tiles: 10}").find("detector_tiles must be in [1, 9]"), std::string::npos);
}

TEST(ConfigFile, LoopClosingSection) {
  const auto defaults = io::parseConfig(kMinimal, "x");
  EXPECT_TRUE(defaults.loop.enabled);
  EXPECT_EQ(defaults.loop.min_inliers, 40);
  const auto c = io::parseConfig(std::string(kMinimal) + "loop: {enabled: false, min_inliers: 60, min_correction_m: 0.1}", "x");
  EXPECT_FALSE(c.loop.enabled);
  EXPECT_EQ(c.loop.min_inliers, 60);
  EXPECT_DOUBLE_EQ(c.loop.min_correction_m, 0.1);
  EXPECT_EQ(defaults.loop.global_ba_iterations, 10);
  EXPECT_EQ(io::parseConfig(std::string(kMinimal) + "loop: {global_ba_iterations: 0}", "x").loop.global_ba_iterations, 0);
  EXPECT_NE(errorOf(std::string(kMinimal) + "loop: {global_ba_iterations: -1}").find("loop.global_ba_iterations must be >= 0"),
            std::string::npos);
  EXPECT_NE(errorOf(std::string(kMinimal) + "loop: {min_inliers: 5}").find("loop.min_inliers must be >= 10"),
            std::string::npos);
  EXPECT_NE(errorOf(std::string(kMinimal) + "loop: {candidates: 0}").find("loop.candidates must be >= 1"),
            std::string::npos);
  EXPECT_NE(errorOf(std::string(kMinimal) + "loop: {min_correction_deg: -1}").find("loop.min_correction_deg must be >= 0"),
            std::string::npos);
  EXPECT_NE(errorOf(std::string(kMinimal) + "loop: {enable: true}").find("unknown key 'loop.enable'"), std::string::npos);
}

TEST(ConfigFile, RelocalisationCandidatesAreACountOrZeroForEveryKeyFrame) {
  EXPECT_EQ(io::parseConfig(kMinimal, "x").tracking.relocalization_candidates, 20);
  EXPECT_EQ(io::parseConfig(std::string(kMinimal) + "tracking: {relocalization_candidates: 0}", "x")
                .tracking.relocalization_candidates,
            0);
  EXPECT_NE(errorOf(std::string(kMinimal) + "tracking: {relocalization_candidates: -1}")
                .find("tracking.relocalization_candidates must be >= 0"),
            std::string::npos);
}

TEST(ConfigFile, LoopWordCandidatesAreACountOrZeroForEveryCandidate) {
  EXPECT_EQ(io::parseConfig(kMinimal, "x").loop.word_candidates, 50);
  EXPECT_EQ(io::parseConfig(std::string(kMinimal) + "loop: {word_candidates: 0}", "x").loop.word_candidates, 0);
  EXPECT_NE(errorOf(std::string(kMinimal) + "loop: {word_candidates: -3}").find("loop.word_candidates must be >= 0"),
            std::string::npos);
}

TEST(ConfigFile, MappingKeyFrameHold) {
  const auto defaults = io::parseConfig(kMinimal, "x");
  EXPECT_DOUBLE_EQ(defaults.mapping.max_keyframe_shift_m, 0);  // off by default
  EXPECT_DOUBLE_EQ(defaults.mapping.max_keyframe_shift_deg, 0);
  const auto on = io::parseConfig(std::string(kMinimal) + "mapping: {max_keyframe_shift_m: 0.03, max_keyframe_shift_deg: 2.5}", "x");
  EXPECT_DOUBLE_EQ(on.mapping.max_keyframe_shift_m, 0.03);
  EXPECT_DOUBLE_EQ(on.mapping.max_keyframe_shift_deg, 2.5);
  EXPECT_NE(errorOf(std::string(kMinimal) + "mapping: {max_keyframe_shift: 1}").find("unknown key 'mapping.max_keyframe_shift'"),
            std::string::npos);
}

TEST(ConfigFile, InvalidValuesAreClearErrors) {
  EXPECT_NE(errorOf("camera: {width: 640, height: 480, fx: 0, fy: 500, cx: 320, cy: 240}").find("fx and fy must be > 0"),
            std::string::npos);
  EXPECT_NE(errorOf("camera: {width: 640, height: 480, fy: 500, cx: 320, cy: 240}").find("missing key 'camera.fx'"),
            std::string::npos);
  EXPECT_NE(errorOf(std::string(kMinimal) + "orb: {featurs: 100}").find("unknown key 'orb.featurs'"),
            std::string::npos);
  EXPECT_NE(errorOf(std::string(kMinimal) + "depth: {factor: -1}").find("depth.factor"), std::string::npos);
  // The line, the value as written and what the key takes.
  EXPECT_NE(errorOf(std::string(kMinimal) + "orb: {features: many}")
                .find("cfg.yaml:2: key 'orb.features' has an invalid value 'many': it takes a whole number"),
            std::string::npos);
  EXPECT_NE(errorOf(std::string(kMinimal) + "dynamic:\n  object_mask: maybe\n")
                .find("cfg.yaml:3: key 'dynamic.object_mask' has an invalid value 'maybe': it takes true or false"),
            std::string::npos);
  EXPECT_NE(errorOf(std::string(kMinimal) + "dynamic: {classes: [0, person]}")
                .find("invalid value '[0, person]': it takes a list of whole numbers"),
            std::string::npos);
  EXPECT_NE(errorOf(std::string(kMinimal) + "depth: {factor: [1, 2]}").find("it takes a number"), std::string::npos);
  EXPECT_NE(errorOf(std::string(kMinimal) + "bogus: 1").find("unknown section 'bogus'"), std::string::npos);
  EXPECT_NE(errorOf("camera: [1, 2").find("not valid YAML"), std::string::npos);
  EXPECT_NE(errorOf("orb: {features: 100}").find("missing section 'camera'"), std::string::npos);
  EXPECT_NE(errorOf(std::string(kMinimal) + "camera2: {}").find("unknown section"), std::string::npos);
  EXPECT_NE(errorOf(std::string(kMinimal) + "dynamic: {box_flow: sometimes}").find("dynamic.box_flow must be auto, on or off"),
            std::string::npos);
  EXPECT_NE(errorOf(std::string(kMinimal) + "dynamic: {centre_gate: -1}").find("centre_gate"), std::string::npos);
  EXPECT_NE(errorOf(std::string(kMinimal) + "dynamic: {unboxed_min_evidence: 0}").find("unboxed_min_evidence must be >= 1"),
            std::string::npos);
  EXPECT_NE(errorOf(std::string(kMinimal) + "dynamic: {unboxed_min_hidden: 1.5}").find("unboxed_min_hidden must be in [0, 1]"),
            std::string::npos);
  EXPECT_NE(errorOf(std::string(kMinimal) + "tracking: {max_predicted_frames: -1}").find("max_predicted_frames must be in [0, 30]"),
            std::string::npos);
  EXPECT_NE(errorOf(std::string(kMinimal) + "tracking: {blur_ratio: 1.5}").find("blur_ratio must be in [0, 1)"),
            std::string::npos);
  EXPECT_NE(errorOf(std::string(kMinimal) + "dynamic: {refill_ratio: 1.2}").find("refill_ratio must be in [0, 1]"),
            std::string::npos);
  EXPECT_NE(errorOf(std::string(kMinimal) + "dynamic: {object_colour: true}").find("object_colour needs dynamic.object_mask"),
            std::string::npos);
  EXPECT_TRUE(io::parseConfig(std::string(kMinimal) + "dynamic: {object_mask: true, object_colour: true}", "t").dynamic.object.colour);
  EXPECT_NE(errorOf(std::string(kMinimal) + "dynamic: {object_region: true}").find("object_region needs dynamic.object_mask"),
            std::string::npos);
  EXPECT_NE(errorOf(std::string(kMinimal) + "dynamic: {object_mask: true, object_region: true, object_colour: true}")
                .find("choose one"),
            std::string::npos);
  EXPECT_NE(errorOf(std::string(kMinimal) + "dynamic: {object_region_step: 0}").find("object_region_step must be in (0, 1]"),
            std::string::npos);
  EXPECT_TRUE(io::parseConfig(std::string(kMinimal) + "dynamic: {object_mask: true, object_region: true}", "t").dynamic.object.region);
  EXPECT_NE(errorOf(std::string(kMinimal) + "dynamic: {object_radius: 100}").find("object_radius must be in [0, 64]"),
            std::string::npos);
  EXPECT_NE(errorOf(std::string(kMinimal) + "dynamic: {object_behind: -0.1}").find("object_behind must be >= 0"),
            std::string::npos);
  EXPECT_NE(errorOf(std::string(kMinimal) + "dynamic: {object_behind_per_size: -1}").find("object_behind_per_size must be"),
            std::string::npos);
  {
    const auto c = io::parseConfig(std::string(kMinimal) + "dynamic: {object_behind_per_size: 0.25}", "t");
    EXPECT_DOUBLE_EQ(c.dynamic.object.behind_per_size, 0.25);
    EXPECT_DOUBLE_EQ(c.dynamic.object.focal_px, c.camera.fy);
  }
  EXPECT_NE(errorOf(std::string(kMinimal) + "tracking: {max_jump_deg: .nan}").find("must be finite"), std::string::npos);
  EXPECT_NE(errorOf(std::string(kMinimal) + "tracking: {excursion_m: -0.01}").find("excursion_m must be >= 0"),
            std::string::npos);
  EXPECT_NE(errorOf(std::string(kMinimal) + "tracking: {covered_ratio: 0}").find("covered_ratio must be > 0"),
            std::string::npos);
  EXPECT_THROW(io::loadConfig("/nonexistent.yaml"), InputError);
}

// Keys where a negative value (or 0) used to mean "off" without saying so, and a thread count that
// hung (10^6) or crashed (INT_MAX) OpenCV's pool.
TEST(ConfigFile, SwitchesAndLimitsOutOfRangeAreClearErrors) {
  const std::string m = kMinimal;
  EXPECT_NE(errorOf(m + "tracking: {max_jump_deg: -1}").find("tracking.max_jump_deg and max_jump_m must be >= 0 (0 = off)"),
            std::string::npos);
  EXPECT_NE(errorOf(m + "tracking: {max_jump_m: -0.1}").find("max_jump_m must be >= 0"), std::string::npos);
  EXPECT_NE(errorOf(m + "mapping: {max_keyframe_shift_m: -1}").find("max_keyframe_shift_deg must be >= 0 (0 = off)"),
            std::string::npos);
  EXPECT_NE(errorOf(m + "mapping: {max_keyframe_shift_deg: -2}").find("max_keyframe_shift_deg must be >= 0"),
            std::string::npos);
  EXPECT_NE(errorOf(m + "dynamic: {reference_max_depth: 0}").find("reference_max_depth and current_max_depth must be > 0"),
            std::string::npos);
  EXPECT_NE(errorOf(m + "dynamic: {current_max_depth: -1}").find("current_max_depth must be > 0"), std::string::npos);
  EXPECT_NE(errorOf(m + "dynamic: {max_patch_std: 0}").find("dynamic.max_patch_std must be > 0"), std::string::npos);
  EXPECT_NE(errorOf(m + "system: {opencv_threads: 1000000}").find("system.opencv_threads must be in [0, 256]"),
            std::string::npos);
  EXPECT_NE(errorOf(m + "system: {opencv_threads: -1}").find("opencv_threads must be in [0, 256]"), std::string::npos);
  // The edges of the ranges are accepted.
  const auto c = io::parseConfig(m + "tracking: {max_jump_deg: 0, max_jump_m: 0}\nsystem: {opencv_threads: 256}", "t");
  EXPECT_EQ(c.opencv_threads, 256);
  EXPECT_DOUBLE_EQ(c.tracking.max_jump_deg, 0);
}

// yaml-cpp returns the first of two equal keys: a value appended to override one above (the usual
// way to try a setting) would be ignored. Both a key and a section written twice are refused.
TEST(ConfigFile, AKeyOrSectionSetTwiceIsAnErrorNotTheFirstValueSilently) {
  const std::string twice = std::string(kMinimal) + "dynamic:\n  occlusion_threshold: 0.4\n  max_age: 3\n"
                                                    "  occlusion_threshold: 0.2\n";
  EXPECT_EQ(errorOf(twice), "cfg.yaml: 'dynamic.occlusion_threshold' is set twice (lines 3 and 5)");
  EXPECT_EQ(errorOf(std::string(kMinimal) + "orb: {features: 500}\norb: {levels: 4}\n"),
            "cfg.yaml: 'orb' is set twice (lines 2 and 3)");
  EXPECT_EQ(errorOf(std::string(kMinimal) + "dynamic:\n  occlusion_threshold: 0.2\n"), "");
}

// Found by fuzz_Config: a YAML complex key ("? ...") made yaml-cpp throw past the InputError net.
TEST(ConfigFile, NonScalarKeysAndNonFiniteValuesAreClearErrors) {
  EXPECT_NE(errorOf("camera: {width: 640, height: 480, fx: 500, fy: 500, cx: 320, cy: 240, ? [a]: 1}")
                .find("not a plain word"),
            std::string::npos);
  EXPECT_NE(errorOf(std::string(kMinimal) + "? {x: 1}: 2").find("not a plain word"), std::string::npos);
  EXPECT_NE(errorOf(std::string(kMinimal) + "dynamic: {confidence: .nan}").find("must be finite"), std::string::npos);
  EXPECT_NE(errorOf("camera: {width: 640, height: 480, fx: .inf, fy: 500, cx: 320, cy: 240}").find("must be finite"),
            std::string::npos);
}

}  // namespace
}  // namespace tkgslam
