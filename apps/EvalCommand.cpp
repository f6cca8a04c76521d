// tkgslam eval GT EST: ATE and RPE exactly as the TUM benchmark scripts compute them.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "Commands.h"
#include "NumberChecks.h"
#include "tkgslam/common/Error.h"
#include "tkgslam/eval/Ate.h"
#include "tkgslam/eval/Rpe.h"
#include "tkgslam/eval/TrajectoryPlot.h"
#include "tkgslam/io/TumDataset.h"
#include "tkgslam/io/InputFile.h"
#include "tkgslam/io/OutputFile.h"

namespace tkgslam::app {

namespace {

struct EvalOptions {
  std::string gt, est, frames, plot, errors;
  bool json = false;
  double delta = 1.0;
  std::string delta_unit = "s";  ///< evaluate_rpe.py's --delta_unit
  // As the TUM scripts' --offset, --scale and (evaluate_ate.py's) --max_difference.
  double offset = 0.0;          ///< seconds added to the estimate's timestamps
  double scale = 1.0;           ///< factor on the estimate's positions
  double max_difference = 0.02; ///< ATE association window, seconds
};

std::string statsJson(const eval::ErrorStatistics& s) {
  return fmt::format(
      "{{\"count\": {}, \"rmse\": {:.6f}, \"mean\": {:.6f}, \"median\": {:.6f}, \"std\": {:.6f}, "
      "\"min\": {:.6f}, \"max\": {:.6f}}}",
      s.count, s.rmse, s.mean, s.median, s.std, s.min, s.max);
}

void printStats(const char* name, const char* unit, const eval::ErrorStatistics& s) {
  std::printf("%s: pairs %d  rmse %.4f  mean %.4f  median %.4f  std %.4f  min %.4f  max %.4f %s\n", name,
              s.count, s.rmse, s.mean, s.median, s.std, s.min, s.max, unit);
}

/// Number of input frames: lines of an image list, or of DIR/rgb.txt.
int countInputFrames(const std::string& path) {
  namespace fs = std::filesystem;
  const fs::path list = fs::is_directory(path) ? fs::path(path) / "rgb.txt" : fs::path(path);
  std::ifstream in = io::openInputFile(list.string(), "frame list");
  return int(io::parseTumImageList(in, list.string()).size());
}

/// One line per associated pose: where the error is (evo's per-pose plots, in a table).
void writeAteErrors(const std::string& path, const eval::AteResult& ate) {
  std::string text = "# timestamp ate_m gt_x gt_y gt_z est_x est_y est_z (metres, estimate aligned to ground truth)\n";
  for (size_t i = 0; i < ate.errors.size(); ++i) {
    const Vec3& g = ate.gt_positions[i];
    const Vec3& e = ate.est_aligned[i];
    text += fmt::format("{:.6f} {:.6f} {:.6f} {:.6f} {:.6f} {:.6f} {:.6f} {:.6f}\n", ate.timestamps[i], ate.errors[i],
                        g.x(), g.y(), g.z(), e.x(), e.y(), e.z());
  }
  io::writeOutputFile(path, "error file", text);
}

int runEval(const EvalOptions& o) {
  const auto gt = io::readTumTrajectory(o.gt);
  auto est = io::readTumTrajectory(o.est);
  if (gt.empty()) throw InputError(fmt::format("ground truth '{}' has no poses", o.gt));
  if (est.empty()) throw InputError(fmt::format("estimate '{}' has no poses", o.est));
  // The scripts add the offset to the estimate's stamps wherever they compare them with the ground
  // truth's: the same as adding it to the estimate's first. The scale is on its positions (ATE),
  // or on its relative translations (RPE, where distances along it stay unscaled).
  for (auto& e : est) e.timestamp += o.offset;
  auto est_scaled = est;
  for (auto& e : est_scaled) e.t *= o.scale;
  const auto ate = eval::computeAte(gt, est_scaled, o.max_difference);
  // A trajectory shorter than the RPE delta still has an ATE: report it, and why there is no RPE.
  const eval::RpeOptions rpe_options{o.delta, eval::parseDeltaUnit(o.delta_unit), o.scale};
  const std::string delta_text = fmt::format("{:g} {}", o.delta, o.delta_unit);
  std::optional<eval::RpeResult> rpe;
  std::string no_rpe;
  try {
    rpe = eval::computeRpe(gt, est, rpe_options);
  } catch (const InputError& e) {
    no_rpe = e.what();
    std::fprintf(stderr, "warning: %s; only ATE reported\n", no_rpe.c_str());
  }
  double tracked_ratio = -1;
  int input_frames = 0;
  if (!o.frames.empty()) {
    input_frames = countInputFrames(o.frames);
    tracked_ratio = input_frames > 0 ? double(est.size()) / input_frames : 0.0;
  }
  if (!o.plot.empty()) eval::writeTrajectorySvg(o.plot, ate, std::filesystem::path(o.est).filename().string());
  if (!o.errors.empty()) writeAteErrors(o.errors, ate);
  if (o.json) {
    std::printf("{\"ground_truth\": \"%s\", \"estimate\": \"%s\", \"estimate_poses\": %zu,\n", o.gt.c_str(),
                o.est.c_str(), est.size());
    std::printf(" \"ate_m\": %s,\n", statsJson(ate.stats).c_str());
    std::printf(" \"offset_s\": %.6f, \"scale\": %.6f, \"max_difference_s\": %.6f,\n", o.offset, o.scale,
                o.max_difference);
    std::printf(" \"rpe_delta\": %g, \"rpe_delta_unit\": \"%s\", \"rpe_delta_s\": %s,\n \"rpe_translation_m\": %s,\n"
                " \"rpe_rotation_deg\": %s",
                o.delta, o.delta_unit.c_str(),
                rpe_options.unit == eval::DeltaUnit::Seconds ? fmt::format("{:.3f}", o.delta).c_str() : "null",
                rpe ? statsJson(rpe->translation).c_str() : "null", rpe ? statsJson(rpe->rotation_deg).c_str() : "null");
    if (tracked_ratio >= 0) {
      std::printf(",\n \"input_frames\": %d, \"tracked_ratio\": %.6f", input_frames, tracked_ratio);
    }
    std::printf("}\n");
  } else {
    std::printf("estimate poses: %zu, ground-truth poses: %zu\n", est.size(), gt.size());
    printStats("ATE", "m", ate.stats);
    if (rpe) {
      printStats(fmt::format("RPE translation ({})", delta_text).c_str(), "m", rpe->translation);
      printStats(fmt::format("RPE rotation    ({})", delta_text).c_str(), "deg", rpe->rotation_deg);
    } else {
      std::printf("RPE (%s): not computed - %s\n", delta_text.c_str(), no_rpe.c_str());
    }
    if (tracked_ratio >= 0) {
      std::printf("tracked frames: %zu / %d = %.2f %%\n", est.size(), input_frames, 100.0 * tracked_ratio);
    }
    if (!o.plot.empty()) std::printf("plot: %s\n", o.plot.c_str());
    if (!o.errors.empty()) std::printf("per-pose errors: %s\n", o.errors.c_str());
  }
  return 0;
}

std::vector<std::string> deltaUnitNames() {
  std::vector<std::string> names;
  for (const auto unit : eval::kDeltaUnits) names.emplace_back(eval::toString(unit));
  return names;
}

}  // namespace

Action addEvalCommand(CLI::App& app) {
  auto opts = std::make_shared<EvalOptions>();
  auto* cmd = app.add_subcommand("eval", "Score a TUM trajectory against ground truth (ATE, RPE)");
  cmd->add_option("ground_truth", opts->gt, "Ground-truth trajectory (TUM format)")->required();
  cmd->add_option("estimate", opts->est, "Estimated trajectory (TUM format)")->required();
  cmd->add_flag("--json", opts->json, "Print the results as JSON");
  cmd->add_option("--plot", opts->plot, "Write an SVG top view of both trajectories, error coloured");
  cmd->add_option("--errors", opts->errors,
                  "Write the per-pose ATE (timestamp, error, aligned positions) to this text file");
  cmd->add_option("--frames", opts->frames,
                  "Input frame list (rgb.txt or a dataset folder) to report the tracked-frame ratio");
  cmd->add_option("--delta", opts->delta, "RPE delta between the poses of a pair, in --delta-unit")
      ->default_val(1.0)
      ->check(positiveNumber());
  cmd->add_option("--delta-unit", opts->delta_unit,
                  "RPE delta unit as evaluate_rpe.py's --delta_unit: s (seconds), f (frames), m, rad or deg "
                  "(travelled along the estimate)")
      ->default_val("s")
      ->check(CLI::IsMember(deltaUnitNames()));
  cmd->add_option("--offset", opts->offset, "Seconds added to the estimate's timestamps (the TUM scripts' --offset)")
      ->default_val(0.0)
      ->check(finiteNumber());
  cmd->add_option("--scale", opts->scale, "Factor on the estimate's positions (the TUM scripts' --scale)")
      ->default_val(1.0)
      ->check(positiveNumber());
  cmd->add_option("--max-difference", opts->max_difference,
                  "ATE: largest time difference (s) of an estimate and a ground-truth pose paired "
                  "(evaluate_ate.py's --max_difference)")
      ->default_val(0.02)
      ->check(positiveNumber());
  return [opts] { return runEval(*opts); };
}

}  // namespace tkgslam::app
