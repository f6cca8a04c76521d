// tkgslam augment: composite real people walking through a real static RGB-D sequence.
#include <cstdio>
#include <filesystem>

#include <fmt/format.h>

#include "Commands.h"
#include "DefaultFile.h"
#include "NumberChecks.h"
#include "tkgslam/augment/SequenceAugmenter.h"
#include "tkgslam/common/Error.h"
#include "tkgslam/io/ConfigFile.h"

namespace tkgslam::app {

namespace {

struct AugmentCliOptions {
  std::string dataset, people, out, config = "configs/tum_fr1.yaml";
  bool whole_people = false;
  augment::AugmentOptions options;
};

int runAugment(const AugmentCliOptions& o) {
  augment::checkAugmentOptions(o.options);  // before the minutes spent cutting people out
  std::error_code ec;
  if (std::filesystem::equivalent(o.out, o.dataset, ec)) {
    throw InputError(fmt::format("augment: --out '{}' is the --dataset folder: the composite would overwrite the "
                                 "original's depth images and lists; give another folder",
                                 o.out));
  }
  const SlamConfig config = io::loadConfig(o.config);
  io::TumDatasetOptions dopt;
  dopt.depth_factor = config.depth.factor;
  dopt.expected_width = config.camera.width;  // the people are projected with this camera
  dopt.expected_height = config.camera.height;
  io::TumDataset dataset(o.dataset, dopt);
  dataset.load(0);  // a depth format it does not take fails now, not after the cut-outs
  const auto gt_path = dataset.groundTruthPath();
  if (!gt_path) throw InputError("augment: the dataset has no groundtruth.txt");
  const auto gt = io::readTumTrajectory(*gt_path);
  augment::checkGroundTruthCovers(dataset, gt, o.options.max_frames);  // before the cut-outs, not after
  auto det_params = config.dynamic.detector;
  // The cut-outs are picked by the letterboxed square detector whatever the run's setting, so one
  // seed gives the same composite as the published benchmark (fitted, 2 more photos yield one).
  det_params.fit_input = false;
  dynamic::YoloDetector detector(det_params);
  std::printf("cutting the people out of the photos in %s\n", o.people.c_str());
  std::fflush(stdout);
  const auto cutouts = augment::extractPersonCutouts(o.people, detector, 150, 0.5f, o.whole_people);
  std::printf("%zu person cut-outs from %s\n", cutouts.size(), o.people.c_str());
  const camera::PinholeCamera camera(config.camera);
  const auto progress = [](int done, int total) {
    if (done % 50 == 0 || done == total) std::fprintf(stderr, "  frame %4d/%d written\n", done, total);
  };
  const auto s =
      augment::augmentSequence(dataset, gt, cutouts, camera, config.depth.factor, o.out, o.options, progress);
  std::printf("wrote %d frames to %s: dynamic pixels mean %.1f %% (max %.1f %%), box ratio T mean %.2f, "
              "T >= 0.7 on %d frames, %d blurred frames\n",
              s.frames, o.out.c_str(), 100 * s.mean_coverage, 100 * s.max_coverage, s.mean_box_ratio,
              s.frames_ratio_over_07, s.blurred);
  for (size_t k = 0; k < s.person_cutouts.size(); ++k) {
    const int c = s.person_cutouts[k];
    std::printf("person %zu: cut-out %d of %zu, from %s\n", k, c + 1, cutouts.size(),
                cutouts[size_t(c)].source.c_str());
  }
  return 0;
}

}  // namespace

Action addAugmentCommand(CLI::App& app) {
  auto o = std::make_shared<AugmentCliOptions>();
  auto* cmd = app.add_subcommand("augment", "Composite real people moving through a static TUM sequence");
  cmd->add_option("-d,--dataset", o->dataset, "Static TUM sequence with groundtruth.txt")->required();
  cmd->add_option("-p,--people", o->people, "Folder of photos with people")->required();
  cmd->add_option("-o,--out", o->out, "Output folder (TUM layout + masks/ + boxes.txt)")->required();
  auto* config = cmd->add_option("-c,--config", o->config, "Camera config (and detector model for the cut-outs)")
                     ->default_val(o->config);
  auto& a = o->options;
  cmd->add_option("--seed", a.seed, "Random seed (same seed, same sequence)")->default_val(1);
  cmd->add_option("--count", a.people, "Number of people")->default_val(1)->check(CLI::Range(1, 20));
  cmd->add_option("--min-size", a.min_size, "Smallest person height, fraction of the image height")->default_val(0.3);
  cmd->add_option("--max-size", a.max_size, "Largest person height, fraction of the image height")->default_val(0.6);
  cmd->add_option("--speed", a.speed, "Peak walking speed, m/s")->default_val(0.3)->check(positiveNumber());
  cmd->add_option("--blur", a.blur_probability, "Share of frames with motion blur")->default_val(0.0)
      ->check(CLI::Range(0.0, 1.0));
  cmd->add_flag("--whole-people", o->whole_people,
                "Only cut-outs of whole upright people (segmented head to feet, box at most 0.45 as wide as tall)");
  cmd->add_flag("--blur-people", a.blur_people_only, "Blur only the people (fast walkers), not the whole frame");
  cmd->add_option("--frames", a.max_frames, "Only the first N frames")->default_val(0)->check(nonNegativeNumber());
  return [o, config] {
    requireDefaultFile(*config, "--config");
    return runAugment(*o);
  };
}

}  // namespace tkgslam::app
