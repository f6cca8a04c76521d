// tkgslam run: SLAM on a TUM-layout RGB-D sequence; writes trajectory, keyframes, map, timings.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <filesystem>

#include <fmt/format.h>
#include <spdlog/spdlog.h>

#include "Commands.h"
#include "FrameEventLog.h"
#include "NumberChecks.h"
#include "tkgslam/common/Error.h"
#include "tkgslam/common/ResidentMemory.h"
#include "tkgslam/eval/Ate.h"
#include "tkgslam/io/ConfigFile.h"
#include "tkgslam/io/OutputFile.h"
#include "tkgslam/io/OutputFolder.h"
#include "tkgslam/io/TrajectoryFile.h"
#include "tkgslam/io/TumDataset.h"
#include "tkgslam/report/HtmlReport.h"
#include "tkgslam/system/SlamSystem.h"

namespace tkgslam::app {

namespace {

struct RunOptions {
  std::string config, dataset, out, mode, debug_dynamic;
  std::string load_map, save_map;  // map files (io/MapFile.h); empty: none
  std::string associations;        // association file instead of rgb.txt / depth.txt; empty: none
  std::string model;               // detector model instead of the config's; empty: the config's
  std::vector<std::string> set;    // "section.key=value" config overrides
  int start_frame = 0;
  bool localize = false;  // track in the loaded map without changing it
  bool deterministic = false;
  bool quiet = false;
  bool report = false;
  int max_frames = 0;
  int loops = 1;
  int detect_every = 0, detector_latency = -1, opencv_threads = -1;  // < default: keep the config's
  double refill_ratio = -1;
  std::string box_flow, unboxed_check, object_mask;                  // empty: keep the config's
  bool lookahead = false;
  int detector_tiles = 0;  // 0: keep the config's
  int detector_size = 0;   // 0: keep the config's
  bool fast = false;       // the detector schedule of bench/modes.sh's TKGf
  std::string pipeline = "on";  // on: a synchronous detector runs one frame ahead (pipelineDetector)
};

/// The signal (SIGINT, SIGTERM) that asked the run to stop; 0 while none did.
std::atomic<int> g_interrupted{0};
extern "C" void onInterrupt(int sig) {
  // A second Ctrl-C does not wait for the outputs: the default action ends the process.
  if (g_interrupted != 0) {
    std::signal(sig, SIG_DFL);
    std::raise(sig);
    return;
  }
  g_interrupted = sig;
}

/// A file's absolute path as a JSON string (quotes, backslashes and control characters escaped),
/// or null for none.
std::string jsonPathOrNull(const std::string& path) {
  if (path.empty()) return "null";
  std::string out = "\"";
  for (const char c : std::filesystem::absolute(path).lexically_normal().string()) {
    if (c == '"' || c == '\\') {
      out += '\\';
      out += c;
    } else if (static_cast<unsigned char>(c) < 0x20) {
      out += fmt::format("\\u{:04x}", int(c));
    } else {
      out += c;
    }
  }
  return out + "\"";
}

void writeText(const std::filesystem::path& p, const std::string& text) {
  io::writeOutputFile(p.string(), "output file", text);
}

/// One JSON object per frame: boxes (detected / predicted), T, and the dropped keypoints.
void writeDynamicDebug(const std::string& path, const std::vector<DynamicFrameInfo>& info) {
  std::string out;
  for (const auto& f : info) {
    out += fmt::format("{{\"timestamp\": {:.6f}, \"T\": {:.4f}, \"geometry\": {}, \"keypoints\": {}, \"dropped\": {}, "
                       "\"readmitted\": {}, \"unboxed\": {}, \"boxes\": [",
                       f.timestamp, f.box_ratio, f.geometry ? "true" : "false", f.keypoints, f.dropped, f.readmitted,
                       f.unboxed);
    for (size_t i = 0; i < f.boxes.size(); ++i) {
      const auto& b = f.boxes[i];
      out += fmt::format("{}{{\"x\": {:.1f}, \"y\": {:.1f}, \"w\": {:.1f}, \"h\": {:.1f}, \"class\": {}, "
                         "\"score\": {:.3f}, \"predicted\": {}, \"track\": {}}}",
                         i ? ", " : "", b.box.x, b.box.y, b.box.width, b.box.height, b.class_id, b.score,
                         b.predicted ? "true" : "false", b.track_id);
    }
    out += "]";
    if (f.missed_dynamic >= 0) out += fmt::format(", \"missed_dynamic\": {}", f.missed_dynamic);
    if (f.late_culled > 0) out += fmt::format(", \"late_culled\": {}", f.late_culled);
    out += ", \"dropped_points\": [";
    for (size_t i = 0; i < f.dropped_points.size(); ++i) {
      out += fmt::format("{}[{:.0f}, {:.0f}]", i ? ", " : "", f.dropped_points[i].x, f.dropped_points[i].y);
    }
    out += "]}\n";
  }
  io::writeOutputFile(path, "dynamic debug file", out);
}

// The configuration the run used - the file with the command line's options applied, every key,
// the model path absolute - so that `tkgslam run -c` on it repeats the run from anywhere.
void writeUsedConfig(const std::filesystem::path& path, SlamConfig config) {
  auto& model = config.dynamic.detector.model;
  if (!model.empty()) model = std::filesystem::absolute(model).lexically_normal().string();
  writeText(path, fmt::format("# The configuration of this run: {} with the command line's options applied.\n",
                              std::filesystem::absolute(config.source).lexically_normal().string()) +
                      io::configToYaml(config));
}

/// A file-based run needs no pose before the next frame is read. So where every frame is detected
/// synchronously (TK / TKG, detect_every 1, latency 0, flow not forced on), the detector runs on
/// frame k + 1 while frame k is tracked: lookahead with latency 1. Every frame still gets its own
/// detection and the Kalman tracker the same updates in the same order, so the boxes and the
/// trajectory are the same (byte for byte in deterministic mode: the static original, 29 composites
/// and all of fr1_xyz, bench/results/detector_input_300.md, session 61), for 22-37 % less time per frame.
void pipelineDetector(SlamConfig& config) {
  const auto& d = config.dynamic;
  if (d.usesKalman() && !d.sparseDetection() && !d.lookahead && !d.usesBoxFlow()) {
    config.dynamic.lookahead = true;
    config.dynamic.detector_latency = 1;
  }
}

/// The configuration file with the command line's options applied. Throws InputError for options
/// that do not go together.
SlamConfig configFor(const RunOptions& o) {
  SlamConfig config = io::loadConfig(o.config, o.set);
  if (o.deterministic) config.deterministic = true;
  if (!o.mode.empty()) config.dynamic.mode = parseDynamicMode(o.mode);
  if (o.detect_every > 0) config.dynamic.detect_every = o.detect_every;
  if (o.detector_latency >= 0) config.dynamic.detector_latency = o.detector_latency;
  if (o.opencv_threads >= 0) config.opencv_threads = o.opencv_threads;
  if (o.refill_ratio >= 0) config.dynamic.refill_ratio = o.refill_ratio;
  if (!o.box_flow.empty()) config.dynamic.box_flow = o.box_flow;
  if (!o.unboxed_check.empty()) config.dynamic.geometry.unboxed_check = o.unboxed_check == "on";
  if (!o.object_mask.empty()) {
    config.dynamic.object_mask = o.object_mask != "off";
    config.dynamic.object.colour = o.object_mask == "colour";
    config.dynamic.object.region = o.object_mask == "region";
  }
  if (o.lookahead) config.dynamic.lookahead = true;
  if (o.detector_tiles > 0) config.dynamic.detector_tiles = o.detector_tiles;
  if (o.detector_size > 0) config.dynamic.detector.input_size = o.detector_size;
  if (!o.model.empty()) config.dynamic.detector.model = o.model;  // relative to the working folder
  if (o.fast) {
    // Every frame detected at 320 x 256 on the detector's own thread, one frame ahead of tracking
    // (the benchmark's TKGf; about the per-frame cost of the tiled schedule it replaced, TKGt, and more
    // accurate on the composites, with poses 1 frame late instead of 15). Options given explicitly win.
    if (config.dynamic.mode != DynamicMode::TK && config.dynamic.mode != DynamicMode::TKG) {
      throw InputError(fmt::format("--fast holds frames for the Kalman box tracker: it needs --mode TK or TKG, not {}",
                                   toString(config.dynamic.mode)));
    }
    config.dynamic.lookahead = true;
    if (o.detect_every <= 0) config.dynamic.detect_every = 1;
    if (o.detector_tiles <= 0) config.dynamic.detector_tiles = 1;
    if (o.detector_size <= 0) config.dynamic.detector.input_size = 320;
    // Each run is used when the next one starts: detect_every x tiles frames later (1).
    if (o.detector_latency < 0) config.dynamic.detector_latency = config.dynamic.detect_every * config.dynamic.detector_tiles;
    if (o.opencv_threads < 0) config.opencv_threads = 1;
  }
  if (config.dynamic.detector_tiles > 1 && !config.dynamic.lookahead) {
    throw InputError("--detector-tiles > 1 needs --lookahead (the tiles are frames still to be tracked)");
  }
  // A latency asked for by name, as an option or with --set, is kept.
  const bool latency_given = o.detector_latency >= 0 || std::any_of(o.set.begin(), o.set.end(), [](const auto& kv) {
                               return kv.rfind("dynamic.detector_latency=", 0) == 0;
                             });
  if (o.pipeline == "on" && !latency_given) pipelineDetector(config);
  return config;
}

io::TumDataset openDataset(const RunOptions& o, const SlamConfig& config) {
  io::TumDatasetOptions dopt;
  dopt.depth_factor = config.depth.factor;
  dopt.expected_width = config.camera.width;
  dopt.expected_height = config.camera.height;
  dopt.loops = o.loops;
  dopt.associations = o.associations;
  io::TumDataset dataset(o.dataset, dopt);
  if (!dataset.associationFile().empty()) spdlog::info("RGB-D pairs from '{}'", dataset.associationFile());
  if (o.start_frame >= dataset.size()) {
    throw InputError(fmt::format("--start-frame {}: the sequence has {} frames", o.start_frame, dataset.size()));
  }
  return dataset;
}

/// Refuses map options that do not go together, and output files that could not be written, now,
/// not after the run.
void checkOptionsBeforeRun(const RunOptions& o) {
  if (o.localize && o.load_map.empty()) {
    throw InputError("--localize tracks in a saved map: give it with --load-map");
  }
  if (o.localize && !o.save_map.empty()) {
    throw InputError("--localize leaves the loaded map as it is: there is nothing new for --save-map to save");
  }
  // Found out before the run, not after it.
  if (!o.save_map.empty()) io::checkWritableFile(o.save_map, "--save-map");
  if (!o.debug_dynamic.empty()) io::checkWritableFile(o.debug_dynamic, "--debug-dynamic");
}

/// Every file `run` may write into its output folder. Those of an earlier run into the same folder
/// are removed first: a stale dynamic.jsonl or report.html would otherwise pass for this run's.
constexpr const char* kRunOutputs[] = {"trajectory.txt", "keyframes.txt",     "map.ply",          "timing.json",
                                       "run.json",       "frame_log.txt",     "memory.tsv",       "config_used.yaml",
                                       "dynamic.jsonl",  "dynamic_eval.json", "report.html"};

void removeEarlierOutputs(const std::filesystem::path& out) {
  int removed = 0;
  for (const char* name : kRunOutputs) {
    std::error_code ec;
    removed += std::filesystem::remove(out / name, ec);
    if (ec) throw InputError(fmt::format("cannot replace '{}': {}", (out / name).string(), ec.message()));
  }
  if (removed > 0) std::printf("replacing the outputs of an earlier run in %s\n", out.string().c_str());
}

/// Writes what the run built into the output folder (and the map file), and the keypoint
/// classification against ground-truth masks when the sequence has them.
void writeOutputs(const RunOptions& o, const SlamConfig& config, const SlamSystem& slam,
                  const std::vector<StampedPose>& traj) {
  const std::filesystem::path out(o.out);
  io::writeTumTrajectory((out / "trajectory.txt").string(), traj);
  io::writeTumTrajectory((out / "keyframes.txt").string(), slam.keyFrameTrajectory());
  io::writePly((out / "map.ply").string(), slam.mapPoints());
  writeText(out / "timing.json", slam.timing().toJson() + "\n");
  if (!o.debug_dynamic.empty()) writeDynamicDebug(o.debug_dynamic, slam.dynamicInfo());
  if (config.dynamic.mode != DynamicMode::Orb) writeDynamicDebug((out / "dynamic.jsonl").string(), slam.dynamicInfo());
  writeUsedConfig(out / "config_used.yaml", config);
  if (!o.save_map.empty()) {
    slam.saveMap(o.save_map);
    std::printf("map saved: %s (%zu keyframes, %zu points)\n", o.save_map.c_str(), slam.keyFrameCount(),
                slam.mapPointCount());
  }
  if (const auto& c = slam.classification(); c.frames > 0) {
    writeText(out / "dynamic_eval.json",
              fmt::format("{{\"frames\": {}, \"true_positive\": {}, \"false_positive\": {}, \"false_negative\": {}, "
                          "\"true_negative\": {}, \"precision\": {:.4f}, \"recall\": {:.4f}}}\n",
                          c.frames, c.true_positive, c.false_positive, c.false_negative, c.true_negative, c.precision(),
                          c.recall()));
    std::printf("dynamic keypoints vs ground-truth masks: precision %.3f, recall %.3f (%d frames)\n", c.precision(),
                c.recall(), c.frames);
  }
  if (config.dynamic.mode != DynamicMode::Orb) {
    const auto& info = slam.dynamicInfo();
    int geometry = 0, kalman_boxes = 0;
    double dropped = 0;
    for (const auto& f : info) {
      geometry += f.geometry;
      kalman_boxes += f.predicted;
      dropped += f.dropped;
    }
    std::printf("dynamic: %zu frames, %d Kalman-filled boxes, geometry check on %d frames, %.1f keypoints "
                "dropped per frame; detector %.1f ms/run\n",
                info.size(), kalman_boxes, geometry, info.empty() ? 0.0 : dropped / info.size(),
                slam.timing().mean("detector"));
  }
}

/// run.json and the summary on stdout. `n`: frames the run covered (read or skipped).
void writeSummary(const RunOptions& o, const SlamConfig& config, const SlamSystem& slam, const io::TumDataset& dataset,
                  const std::vector<StampedPose>& traj, int n, const FrameEventLog::Counts& events) {
  const double ratio = n > 0 ? double(traj.size()) / n : 0.0;
  writeText(std::filesystem::path(o.out) / "run.json",
            fmt::format("{{\"tkgslam_version\": \"{}\", \"dataset\": {}, \"config\": {}, \"mode\": \"{}\", "
                        "\"deterministic\": {}, "
                        "\"frames\": {}, \"tracked\": {}, \"tracked_ratio\": {:.4f}, \"predicted\": {}, "
                        "\"interpolated_lost\": {}, \"blurred\": {}, \"skipped\": {}, "
                        "\"keyframes\": {}, \"keyframes_held\": {}, \"loops_closed\": {}, "
                        "\"map_points\": {}, \"mean_ms_per_frame\": {:.2f}, \"median_ms_per_frame\": {:.2f}, "
                        "\"ratio_threshold\": {}, \"start_frame\": {}, \"map_loaded\": {}, \"map_saved\": {}, \"localization_only\": {}, "
                        "\"associations\": {}}}\n",
                        TKGSLAM_VERSION, jsonPathOrNull(o.dataset), jsonPathOrNull(o.config),
                        toString(config.dynamic.mode),
                        config.deterministic ? "true" : "false", n, traj.size(), ratio, events.predicted,
                        events.interpolated, events.blurred, events.skipped, slam.keyFrameCount(),
                        slam.mappingStats().keyframes_held, slam.loopStats().closed, slam.mapPointCount(),
                        slam.timing().mean("total"), slam.timing().median("total"),
                        config.dynamic.geometry.ratio_threshold, o.start_frame, jsonPathOrNull(o.load_map),
                        jsonPathOrNull(o.save_map), o.localize ? "true" : "false",
                        jsonPathOrNull(dataset.associationFile())));
  std::printf("frames %d, tracked %zu (%.2f %%; %d of them predicted, %d lost and then interpolated), blurred %d, "
              "skipped %d (unreadable), lost %d, keyframes %zu, map points %zu%s\n",
              n, traj.size(), 100.0 * ratio, events.predicted, events.interpolated, events.blurred, events.skipped,
              events.lost, slam.keyFrameCount(), slam.mapPointCount(),
              events.skipped + events.lost + events.predicted + events.blurred > 0 ? " - see frame_log.txt" : "");
  if (events.segments > 0) {
    std::printf("tracking was lost for good %d time(s): %d new map segment(s), %d re-anchored to the one before\n",
                events.segments, events.segments, events.reanchored);
  }
  if (const int held = slam.mappingStats().keyframes_held; held > 0) {
    std::printf("local BA held %d new keyframe(s) where tracking put them (it moved them further than "
                "mapping.max_keyframe_shift_m / _deg)\n", held);
  }
  if (const auto ls = slam.loopStats(); ls.closed > 0) {
    const double checked = std::max(ls.keyframes_checked, 1);
    std::printf("loops closed: %d (loops found %d, %d of them where the map already had the camera; per keyframe "
                "checked %.1f ms and %.1f old keyframes matched%s; %d global bundle adjustment(s), the last %.0f ms)\n",
                ls.closed, ls.detected + ls.consistent, ls.consistent, ls.total_ms / checked,
                ls.candidates_considered / checked, ls.vocabulary_trainings ? ", the most similar by words" : "",
                ls.global_bundles, ls.last_global_ba_ms);
  }
  std::printf("time per frame: mean %.1f ms, median %.1f ms (ORB+tracking median %.1f ms)\n",
              slam.timing().mean("total"), slam.timing().median("total"), slam.timing().median("orb_and_tracking"));
  if (const auto gt_path = dataset.groundTruthPath(); gt_path && traj.size() >= 2 && o.loops == 1) {
    try {
      const auto ate = eval::computeAte(io::readTumTrajectory(*gt_path), io::toTrajectoryEntries(traj));
      std::printf("ATE RMSE %.4f m (%d poses)\n", ate.stats.rmse, ate.stats.count);
    } catch (const InputError& e) {
      // The run's outputs stand; only the score against a ground truth that does not fit is missing.
      spdlog::warn("ATE not computed against {}: {}", *gt_path, e.what());
    }
  }
}

/// A run whose first this many frames are all unreadable stops there: the sequence's format is wrong.
constexpr int kUnreadableStart = 20;
/// Skipped frames warned about on the console; frame_log.txt lists them all.
constexpr int kSkipWarnings = 10;

/// Reads frame `i` into `images`. A frame that cannot be read is logged and skipped (returns false):
/// one bad frame in a run is not fatal.
bool readFrame(const io::TumDataset& dataset, int i, FrameEventLog& events, io::RgbdImages& images) {
  try {
    images = dataset.load(i);
    return true;
  } catch (const InputError& e) {
    const int skipped = events.counts().skipped;
    if (skipped < kSkipWarnings) spdlog::warn("frame {} skipped: {}", i, e.what());
    if (skipped == kSkipWarnings) spdlog::warn("more frames skipped: frame_log.txt lists them all");
    events.addSkipped(dataset.timestamp(i), e.what());
    return false;
  }
}

int runSlam(const RunOptions& o) {
  const SlamConfig config = configFor(o);
  io::TumDataset dataset = openDataset(o, config);
  checkOptionsBeforeRun(o);

  SlamSystem slam(config);
  if (!o.load_map.empty()) {
    const size_t kfs = slam.loadMap(o.load_map, o.localize);
    std::printf("loaded map %s: %zu keyframes, %zu points; relocalising in it%s\n", o.load_map.c_str(), kfs,
                slam.mapPointCount(), o.localize ? " (localisation only: the map is not changed)" : "");
  }
  io::createOutputFolder(o.out);
  const std::filesystem::path out(o.out);
  removeEarlierOutputs(out);
  const int first = o.start_frame;
  const int end = o.max_frames > 0 ? std::min(first + o.max_frames, dataset.size()) : dataset.size();
  int n = end - first;
  const auto& dyn = config.dynamic;
  const bool one_ahead = dyn.usesLookahead() && dyn.lookaheadDelay() == 1 && dyn.detect_every == 1;
  std::printf("tkgslam run: %d frames from %s (%s, dynamic mode %s%s)\n", n, o.dataset.c_str(),
              config.deterministic ? "deterministic" : "threaded", toString(dyn.mode),
              one_ahead ? ", detector one frame ahead" : "");
  int processed = 0;
  bool stopped_early = false;  // the first frames were all unreadable
  // Frames that produced no pose, only a predicted one or were blurred, and why.
  FrameEventLog events(out / "frame_log.txt");
  // Resident memory every 100 frames: long (--loops) runs must stay flat once the map stops growing.
  io::OutputLog memory_log((out / "memory.tsv").string(), "memory log");
  memory_log.write("frame\trss_mib\tkeyframes\tmap_points\n");
  // Ctrl-C or SIGTERM stops after the current frame; everything computed so far is still written.
  g_interrupted = 0;
  const auto previous_int = std::signal(SIGINT, onInterrupt);
  const auto previous_term = std::signal(SIGTERM, onInterrupt);
  const auto started = std::chrono::steady_clock::now();
  for (int i = first; i < end && !g_interrupted; ++i) {
    io::RgbdImages images;
    if (!readFrame(dataset, i, events, images)) {
      // A whole sequence in a format load() does not take fails frame by frame: stop, not after all of it.
      if (processed == 0 && events.counts().skipped == kUnreadableStart && i + 1 < end) {
        stopped_early = true;
        break;
      }
      continue;
    }
    ++processed;
    // (With lookahead a frame's outcome arrives some frames after the frame itself.)
    for (const auto& f : slam.processFrame(images)) events.add(f);
    const int done = i + 1 - first;
    if (done % 100 == 0 || done == n) {
      memory_log.write(
          fmt::format("{}\t{:.1f}\t{}\t{}\n", done, residentMemoryMiB(), slam.keyFrameCount(), slam.mapPointCount()));
    }
    if (!o.quiet && (done % 50 == 0 || done == n)) {
      // Time left at the wall-clock pace so far (the map's growth slows later frames a little).
      const double elapsed_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
      const long left_s = std::lround(elapsed_s / done * (n - done));
      const std::string left = done < n ? fmt::format("  {}:{:02d} left", left_s / 60, left_s % 60) : "";
      std::fprintf(stderr,
                   "  frame %4d/%d  tracked %5.1f%%  keyframes %3zu  map points %5zu  %.1f ms/frame  %.0f MiB%s\n", done, n, 100.0 * slam.framesTracked() / std::max(1, slam.framesProcessed()), slam.keyFrameCount(),
                   slam.mapPointCount(), slam.timing().mean("total"), residentMemoryMiB(), left.c_str());
    }
  }
  std::signal(SIGINT, previous_int);
  std::signal(SIGTERM, previous_term);
  if (g_interrupted) {
    n = processed + events.counts().skipped;  // the summary covers the frames actually read
    std::printf("interrupted (%s) after %d frames: writing what was computed\n",
                g_interrupted == SIGTERM ? "SIGTERM" : "SIGINT", n);
  }
  if (stopped_early) n = events.counts().skipped;  // the summary covers the frames tried
  for (const auto& f : slam.finish()) events.add(f);
  events.finish();
  memory_log.finish();

  const auto traj = slam.trajectory();
  writeOutputs(o, config, slam, traj);
  writeSummary(o, config, slam, dataset, traj, n, events.counts());
  if (o.report) std::printf("report: %s\n", report::writeHtmlReport(o.out).c_str());
  std::printf("outputs: %s/{trajectory.txt, keyframes.txt, map.ply, timing.json, run.json, frame_log.txt, memory.tsv}\n",
              o.out.c_str());
  if (processed == 0 && events.counts().skipped > 0 && !g_interrupted) {
    // Outputs are written (frame_log.txt says why each frame failed), but an empty trajectory is no result.
    throw InputError(fmt::format("no frame could be read ({} tried{}; see {}/frame_log.txt). The first: {}{}",
                                 events.counts().skipped, stopped_early ? ", the rest not" : "", o.out,
                                 events.firstSkipReason(),
                                 stopped_early ? ". (If only the start is bad, --start-frame skips it.)" : ""));
  }
  if (o.load_map.empty() && traj.empty() && processed > 0 && !g_interrupted) {
    // The map never started: an empty trajectory is no result, and the cause is nearly always the depth.
    throw InputError(fmt::format(
        "no frame was tracked: none of the {} frames had tracking.min_init_features ({}) keypoints with depth to "
        "start a map (see {}/frame_log.txt). Check depth.factor ({} raw units per metre), depth.max_depth ({} m) "
        "and that the depth images are not empty",
        processed, config.tracking.min_init_features, o.out, config.depth.factor, config.depth.max_depth));
  }
  if (o.localize && traj.empty() && processed > 0 && !g_interrupted) {
    // Nothing to show for the run: most likely a map of another place (or another sequence's camera).
    throw InputError(fmt::format("--localize: the camera was not found in the map '{}' on any of the {} frames",
                                 o.load_map, processed));
  }
  return g_interrupted ? 128 + g_interrupted : 0;  // the shell's code for a process ended by the signal
}

}  // namespace

Action addRunCommand(CLI::App& app) {
  auto o = std::make_shared<RunOptions>();
  auto* cmd = app.add_subcommand("run", "Run RGB-D SLAM on a TUM-layout sequence");
  cmd->add_option("-c,--config", o->config, "Camera/system YAML config (see configs/)")->required();
  cmd->add_option("--set", o->set,
                  "Override one config key, as section.key=value (YAML value; repeat for more, e.g. --set "
                  "dynamic.max_age=5 --set tracking.max_jump_m=0.05); the options below win over it")
      ->allow_extra_args(false);
  cmd->add_option("-d,--dataset", o->dataset,
                  "Sequence folder with rgb.txt and depth.txt (or see --associations)")
      ->required();
  cmd->add_option("--associations", o->associations,
                  "Take the RGB-D pairs from this association file (ORB-SLAM2's, associate.py's: 'timestamp file "
                  "timestamp file' per line, names relative to --dataset) instead of rgb.txt and depth.txt");
  cmd->add_option("-o,--out", o->out, "Output folder")->required();
  cmd->add_flag("--deterministic", o->deterministic,
                "Same input, same trajectory bit for bit (mapping runs in step with tracking)");
  cmd->add_option("--max-frames", o->max_frames, "Process only the first N frames")->check(nonNegativeNumber());
  cmd->add_option("--start-frame", o->start_frame, "Start at the N-th frame of the sequence (0 = the first)")
      ->check(nonNegativeNumber());
  cmd->add_option("--load-map", o->load_map,
                  "Start in a map saved by an earlier run (--save-map): relocalise in it and extend it; poses come out "
                  "in its world frame");
  cmd->add_option("--save-map", o->save_map, "Save the map at the end of the run to this file, for --load-map");
  cmd->add_flag("--localize", o->localize,
                "With --load-map: track in the loaded map without changing it (no keyframes or points of this run; "
                "lost frames stay lost until it relocalises)");
  cmd->add_option("--loops", o->loops, "Play the sequence N times (soak test)")->check(positiveNumber());
  cmd->add_flag("-q,--quiet", o->quiet, "No progress lines");
  cmd->add_flag("--report", o->report, "Also write OUT/report.html (plots, 3-D view, timings)");
  cmd->add_option("--model", o->model,
                  "YOLOv5 ONNX model for the dynamic modes (overrides dynamic.model, which is relative to the config)");
  cmd->add_option("--mode", o->mode, "Dynamic handling: orb, T, TK, TG or TKG (overrides dynamic.mode)");
  cmd->add_option("--detect-every", o->detect_every, "Run the detector on every N-th frame (overrides the config)")
      ->check(positiveNumber());
  cmd->add_option("--detector-latency", o->detector_latency,
                  "Use each detection L frames later, tracking meanwhile (0 = wait; overrides the config)")
      ->check(nonNegativeNumber());
  cmd->add_option("--box-flow", o->box_flow, "Move boxes by optical flow between detections: auto, on, off")
      ->check(CLI::IsMember({"auto", "on", "off"}));
  cmd->add_option("--unboxed-check", o->unboxed_check,
                  "G modes: also look for movers outside the boxes on every frame (on; off = the paper's TG/TKG)")
      ->check(CLI::IsMember({"on", "off"}));
  cmd->add_option("--object-mask", o->object_mask,
                  "Exclude only what in each box may be the object by depth (on), by depth and colour (colour), "
                  "as the region a depth edge bounds (region), or the whole box (off = the paper)")
      ->check(CLI::IsMember({"on", "colour", "region", "off"}));
  cmd->add_flag("--lookahead", o->lookahead,
                "Hold frames back until the next detection (boxes interpolated; poses N + L - 1 frames late)");
  cmd->add_option("--detector-tiles", o->detector_tiles,
                  "With --lookahead: frames per detector run, tiled into one input (4 = 2x2 at half size)")
      ->check(CLI::Range(1, 9));
  cmd->add_option("--detector-size", o->detector_size,
                  "Detector input's long side in pixels, a multiple of 32 (640 = the export's; 320: ~5 times faster, "
                  "large people found as well; overrides dynamic.input_size)")
      ->check([](const std::string& v) {
        using dynamic::DetectorParams;
        int n = 0;
        return CLI::detail::lexical_cast(v, n) && DetectorParams::validInputSize(n)
                   ? std::string()
                   : fmt::format("must be a multiple of 32 from 64 to {}", DetectorParams::kMaxInputSize);
      });
  cmd->add_flag("--fast", o->fast,
                "TK/TKG: every frame detected at about the cost of ORB tracking: --detector-size 320 --lookahead "
                "--detector-latency 1 --opencv-threads 1 (the detector runs one frame ahead, poses come 1 frame late; "
                "options given explicitly win)");
  cmd->add_option("--pipeline", o->pipeline,
                  "TK/TKG with every frame detected: on = the detector works on the next frame while this one is "
                  "tracked (same trajectory, ~30 % less time; the run's config_used.yaml records it as lookahead with "
                  "latency 1); off = each frame waits for its own detection, as a live camera's would. "
                  "--detector-latency (or --set dynamic.detector_latency=) given explicitly turns it off")
      ->check(CLI::IsMember({"on", "off"}));
  cmd->add_option("--refill-ratio", o->refill_ratio,
                  "Boxes cover at least this share: extract ORB again outside them (0 = off; overrides the config)")
      ->check(CLI::Range(0.0, 1.0));
  cmd->add_option("--opencv-threads", o->opencv_threads, "OpenCV's thread pool size (0 = default)")
      ->check(CLI::Range(0, SlamConfig::kMaxOpenCvThreads));
  cmd->add_option("--debug-dynamic", o->debug_dynamic,
                  "Write per-frame boxes, T and dropped keypoints as JSON lines to this file");
  return [o] { return runSlam(*o); };
}

Action addReportCommand(CLI::App& app) {
  auto dir = std::make_shared<std::string>();
  auto* cmd = app.add_subcommand("report", "Write OUTDIR/report.html for the output folder of a run");
  cmd->add_option("outdir", *dir, "Output folder of `tkgslam run`")->required();
  return [dir] {
    std::printf("report: %s\n", report::writeHtmlReport(*dir).c_str());
    return 0;
  };
}

}  // namespace tkgslam::app
