#pragma once
// Which keypoints may be used for tracking and mapping (the paper's §3.3, DESIGN.md):
//  - the ratio gate: T = area(union of boxes) / image area;
//  - T < tau (or no geometry in the mode): every keypoint inside a box is dynamic;
//  - T >= tau: a multi-view geometry check against the nearest keyframes finds where static
//    structure seen before is now hidden by something nearer (depth occlusion); the depth-
//    consistent region grown from that evidence is dynamic, the rest of the boxes is static.
// Images and masks are in raw (distorted) pixels, like the depth image.
#include <memory>
#include <vector>

#include <opencv2/core.hpp>

#include "tkgslam/camera/PinholeCamera.h"
#include "tkgslam/common/Pose.h"
#include "tkgslam/data/FrameFeatures.h"
#include "tkgslam/dynamic/Detection.h"

namespace tkgslam::dynamic {

struct GeometryParams {
  double ratio_threshold = 0.7;      ///< tau of the ratio gate
  int reference_keyframes = 3;       ///< nearest keyframes by vDist
  double reference_max_depth = 6.0;  ///< m, reference keypoints used
  double current_max_depth = 7.0;    ///< m, projected depth accepted
  double max_parallax_deg = 30.0;    ///< angle between the two viewing rays
  double occlusion_threshold = 0.4;  ///< m, z_proj - z' above this is dynamic evidence
  int patch_radius = 3;              ///< px, patch searched around the projection
  double max_patch_std = 0.3;        ///< m, a patch with more depth spread is a complex edge: static
  double region_depth_step = 0.05;   ///< m, neighbour depth step allowed when growing a region
  /// Box keypoints on an occluding outline are not re-admitted: something within this radius (px; 16
  /// = the ORB patch's at level 0) is more than occluder_depth nearer than the keypoint. Where a
  /// person's outline crosses the background, the corner and its descriptor move with the person
  /// while the depth there is the background's, which the depth test above cannot see (extreme_s22
  /// composite, TKG: 0.2019 -> 0.0143 m; but the lookahead mode TKGt loses more frames with it,
  /// see bench/results/extreme_sensitivity_300.md, session 24). 0 = off (the default).
  int occluder_radius = 0;
  double occluder_depth = 0.1;  ///< m
  /// Movers the detector missed: the same check outside the boxes, on every frame (see
  /// findUnboxedMovers). Not in the paper.
  bool unboxed_check = true;
  int unboxed_min_evidence = 15;      ///< hidden reference points a region needs to count as a mover
  double unboxed_depth_range = 0.3;   ///< m, a region's depths stay within this of its seed's
  double unboxed_min_hidden = 0.5;    ///< share of the reference points projected into a region that are hidden
};

/// A keyframe as the geometry check sees it.
struct ReferenceView {
  Pose T_cw;
  std::shared_ptr<const data::FrameFeatures> features;
};

/// Rasterised boxes: 255 inside any box. `ratio` = area(union) / image area.
struct BoxMask {
  cv::Mat mask;
  double ratio = 0;
};
/// Each box is widened by `margin` x its width (height) on the left and right (top and bottom):
/// detector boxes are tight and limbs of moving people stick out of them.
BoxMask rasterizeBoxes(const std::vector<Detection>& boxes, cv::Size image, double margin = 0.0);

/// See objectMaskInBoxes.
struct ObjectMaskParams {
  double behind = 0.5;  ///< m, depth behind the object's median still counted as the object
  /// > 0: `behind` is this share of the object's size instead - the larger side of its box in metres
  /// at the median depth (px x depth / focal_px) - as a body's depth extent scales with its size.
  double behind_per_size = 0;
  double focal_px = 0;  ///< px, converts box sizes to metres (needed with behind_per_size)
  int radius = 16;      ///< px, the ORB patch radius at level 0 (31 x 31 patch)
  /// Segment the object by colour too: GrabCut seeded by depth (see objectMaskInBoxes).
  bool colour = false;
  /// Segment the object as the depth-connected region around its median depth (see objectMaskInBoxes).
  bool region = false;
  /// Region growing: the largest depth step between neighbouring pixels inside one object, as a
  /// share of the depth (across a body's surface a pixel's step is well under 1 %; its outline
  /// against the background is tens of %).
  double region_step = 0.05;
};
/// Where in the boxes the objects may be, from depth (not in the paper). Each box's object is at the
/// median depth of the box's central half (width and height); its pixels no more than `behind` metres
/// behind that, nearer ones and those without depth may be the object, widened by `radius` px (a
/// keypoint whose ORB patch overlaps a mover moves with it) and kept inside the widened box. Only
/// what lies clearly behind the object - the background seen around it - is left out. A box without
/// depth in its centre is masked whole. `depth_m`: CV_32F metres, 0 = no depth (no NaN), same size
/// as the image; `ratio` = masked area / image area.
/// With `params.colour`, the object inside the box is what GrabCut (on a quarter-size crop of the
/// box and 15 % around it, `bgr` CV_8UC3) separates from its background, seeded by depth: outside
/// the box and more than `behind` behind the median certain background, inside the box within 3 cm
/// of the median certain object, the rest probable object (in the box) or background (around it).
/// Background nearer than `behind` is then left out too. Falls back to the depth mask where GrabCut
/// has too few seeds of one side or fails.
/// With `params.region`, the object is the region grown (4-neighbours, full resolution) from the
/// pixels of the box's central half within `region_step` of the median, through neighbours whose
/// depths differ by at most `region_step` x depth, within `behind` and the widened box plus the
/// radius; nearer pixels and those without depth stay in the mask (a median that fell on the
/// background must not free the object). Scale-free: what it leaves out is what a depth edge
/// separates from the object, at any distance.
BoxMask objectMaskInBoxes(const std::vector<Detection>& boxes, const cv::Mat& bgr, const cv::Mat& depth_m,
                          double margin, const ObjectMaskParams& params);

/// What of the boxes is excluded: the object mask (objectMaskInBoxes) with `object`, else the whole
/// boxes (rasterizeBoxes). `ratio` is the boxes' share of the view either way: the paper's T, which
/// the refill, the geometry check and the covered-frame rule read.
BoxMask dynamicMask(const std::vector<Detection>& boxes, const cv::Mat& bgr, const cv::Mat& depth_m, double margin,
                    const ObjectMaskParams* object);

/// The pixel nearest p is inside the image and non-zero in the 8-bit mask.
bool inMask(const cv::Mat& mask, const cv::Point2f& p);

/// Marks every keypoint inside the mask as excluded; returns how many were not excluded before.
int excludeKeypointsInMask(data::FrameFeatures& features, const cv::Mat& mask);

/// Picks up to `n` keyframes nearest to the current pose by vDist = 0.7 vTrans + 0.3 vRot, each
/// term divided by its maximum over the candidates (translation between camera centres;
/// rotation as the norm of the Euler-angle difference). Returns indices into `candidates`.
std::vector<int> selectReferenceViews(const Pose& T_cw, const std::vector<Pose>& candidates_T_cw, int n);

struct GeometryResult {
  cv::Mat dynamic_region;  ///< 255 where the check found a moving object (inside the boxes)
  int evidence = 0;        ///< reference points found hidden behind nearer structure
  int projected = 0;       ///< reference points that passed the angle/depth/image tests
};

/// Runs the multi-view geometry check for the current frame (pose T_cw, depth in metres).
GeometryResult checkMultiViewGeometry(const Pose& T_cw, const cv::Mat& depth_m, const cv::Mat& box_mask,
                                      const std::vector<ReferenceView>& references,
                                      const camera::PinholeCamera& camera, const GeometryParams& params);

/// The geometry check's evidence outside the boxes (all of the image if `box_mask` is empty): a
/// mover the detector missed hides static structure the reference keyframes saw. Each connected
/// surface within unboxed_depth_range of an evidence pixel's depth is a region; a region with at
/// least unboxed_min_evidence evidence pixels, which are at least unboxed_min_hidden of the
/// reference points projected into it, is a mover. Within it the dynamic region is regrown from the
/// evidence with region_depth_step (so it stops where the mover's depth jumps to a touching surface).
GeometryResult findUnboxedMovers(const Pose& T_cw, const cv::Mat& depth_m, const cv::Mat& box_mask,
                                 const std::vector<ReferenceView>& references,
                                 const camera::PinholeCamera& camera, const GeometryParams& params);

/// Re-admits keypoints inside the boxes that are not in the dynamic region; returns how many.
/// Keypoints with depth that have something nearer within GeometryParams::occluder_radius
/// (`depth_m`: CV_32F metres, 0 = none; empty = no such test) stay excluded.
int readmitStaticKeypoints(data::FrameFeatures& features, const cv::Mat& box_mask, const cv::Mat& dynamic_region,
                           const cv::Mat& depth_m, const GeometryParams& params);

}  // namespace tkgslam::dynamic
