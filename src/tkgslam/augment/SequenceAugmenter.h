#pragma once
// Builds a dynamic RGB-D sequence with exact ground truth from real parts: a real static TUM
// sequence (real camera trajectory) and real people cut out of photos, each walking its own 3-D
// path in the world (independent of the camera), so its pixels move inconsistently with the camera
// motion. The person's depth overwrites the depth image where it is nearer than the background,
// so the geometry check has a real occlusion to find. Deterministic for a given seed.
//
// Output (TUM layout): rgb/, depth/, rgb.txt, depth.txt, groundtruth.txt (copied), plus
// masks/ (255 = dynamic pixel) and boxes.txt ("timestamp person x y w h", raw pixels).
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "tkgslam/augment/PersonCutout.h"
#include "tkgslam/camera/PinholeCamera.h"
#include "tkgslam/io/TrajectoryFile.h"
#include "tkgslam/io/TumDataset.h"

namespace tkgslam::augment {

struct AugmentOptions {
  int people = 1;
  double min_size = 0.3;      ///< person height on screen at its mean distance, fraction of image height
  double max_size = 0.6;
  double speed = 0.3;         ///< m/s, peak walking speed across the view
  double blur_probability = 0.0;  ///< share of frames with strong motion blur (detector misses)
  int blur_kernel = 31;       ///< px, length of the motion-blur kernel
  /// Blur only the people (a fast walker smeared in front of a sharp background: the detector
  /// misses while the camera can still track) instead of the whole frame (camera shake).
  bool blur_people_only = false;
  std::uint64_t seed = 1;
  int max_frames = 0;         ///< 0 = the whole sequence
  int jpeg_quality = 95;
};

struct AugmentStats {
  int frames = 0;
  double mean_coverage = 0;   ///< dynamic pixels / image, mean over frames
  double max_coverage = 0;
  double mean_box_ratio = 0;  ///< union of the person boxes / image
  int frames_ratio_over_07 = 0;
  int blurred = 0;
  /// Per person id (as in boxes.txt): the index of its cut-out in the cut-outs passed in.
  std::vector<int> person_cutouts;
};

/// Throws InputError unless people >= 1 and 0 < min_size <= max_size <= 1.5.
void checkAugmentOptions(const AugmentOptions& options);

/// Largest distance (s) from a frame to its nearest ground-truth pose (fr1_xyz: 0.041 s at most).
constexpr double kMaxGroundTruthGap = 0.1;

/// Throws InputError unless every frame to be composited (the first `max_frames`, 0 = all) has a
/// ground-truth pose within kMaxGroundTruthGap: the people are placed with the camera's true pose,
/// and stamps in another unit or a ground truth of another part of the sequence would give wrong ones.
void checkGroundTruthCovers(const io::TumDataset& dataset, const std::vector<io::TrajectoryEntry>& ground_truth,
                            int max_frames);

/// Called after each frame written: frames done and the total.
using AugmentProgress = std::function<void(int done, int total)>;

/// Writes the composite sequence to `out_dir`. Throws InputError on invalid options (as
/// checkAugmentOptions) and I/O problems.
AugmentStats augmentSequence(const io::TumDataset& dataset, const std::vector<io::TrajectoryEntry>& ground_truth,
                             const std::vector<PersonCutout>& cutouts, const camera::PinholeCamera& camera,
                             double depth_factor, const std::string& out_dir, const AugmentOptions& options,
                             const AugmentProgress& progress = {});

}  // namespace tkgslam::augment
