#pragma once
// A bundle adjustment problem copied out of the map, and its solution written back. Local BA
// (a keyframe's covisible window) and global BA after a loop closure (every active keyframe)
// build the same problem from different windows: the window's keyframes are free, every other
// keyframe that sees one of their points is held fixed, and so is the map's first keyframe (it
// holds the gauge). The copy lets the solver run without the map lock.
#include <memory>
#include <set>
#include <utility>
#include <vector>

#include "tkgslam/data/Map.h"
#include "tkgslam/feature/ScalePyramid.h"
#include "tkgslam/optimize/LocalBundleAdjuster.h"

namespace tkgslam::optimize {

class MapBundle {
 public:
  /// Copies the window's keyframes and every point they see, with all its observations in
  /// non-bad keyframes (ideal pixels, right-image u where there is depth, weights by pyramid
  /// level). Map lock held by the caller.
  MapBundle(const data::Map& map, const std::vector<data::KeyFrame*>& window, const feature::ScalePyramid& pyramid);

  /// Holds one more keyframe fixed (e.g. a segment's oldest when keyframe 0 is not in it).
  void fix(const data::KeyFrame* kf);

  BundleProblem& problem() { return problem_; }
  const std::vector<std::shared_ptr<data::KeyFrame>>& keyFrames() const { return cams_; }
  /// Whether the point is one of the problem's.
  bool contains(const data::MapPoint& mp) const { return taken_.count(&mp) > 0; }

  /// Writes a solution back (map lock held by the caller): removes the outlier observations
  /// (`outlier` per problem observation, as solveBundle returns it), sets the free keyframes'
  /// poses and moves the points (normal and depth range refreshed).
  void apply(data::Map& map, const std::vector<char>& outlier, const feature::ScalePyramid& pyramid) const;

 private:
  BundleProblem problem_;
  std::vector<std::shared_ptr<data::KeyFrame>> cams_;     ///< per problem pose
  std::vector<std::shared_ptr<data::MapPoint>> points_;   ///< per problem point
  std::vector<std::pair<data::KeyFrame*, data::MapPoint*>> observed_;  ///< per observation
  std::set<const data::MapPoint*> taken_;
};

}  // namespace tkgslam::optimize
