#pragma once
// A frame being tracked: its features, the map points matched to its keypoints, and its pose.
#include <memory>
#include <vector>

#include "tkgslam/common/Pose.h"
#include "tkgslam/data/FrameFeatures.h"
#include "tkgslam/data/KeyFrame.h"
#include "tkgslam/data/MapPoint.h"

namespace tkgslam::data {

struct Frame {
  Frame(long id_, double timestamp_, std::shared_ptr<FrameFeatures> f)
      : id(id_), timestamp(timestamp_), features(std::move(f)) {
    map_points.resize(features->size());
    outlier.assign(features->size(), 0);
  }

  long id;
  double timestamp;  ///< seconds
  std::shared_ptr<FrameFeatures> features;  ///< mutable until the frame becomes a keyframe (exclusions)
  std::vector<std::shared_ptr<MapPoint>> map_points;  ///< per keypoint, may be null
  std::vector<char> outlier;                          ///< per keypoint, set by pose optimisation
  Pose T_cw = Pose::Identity();                       ///< world -> camera
  std::shared_ptr<KeyFrame> reference;                ///< keyframe the pose is stored relative to
  double box_cover = 0;  ///< share of the image inside dynamic-object boxes (0 without a detector)

  Vec3 centre() const { return T_cw.inverse().translation(); }
  int size() const { return features->size(); }
  int countMatches() const {
    int n = 0;
    for (int i = 0; i < size(); ++i) n += (map_points[i] && !outlier[i]);
    return n;
  }
};

}  // namespace tkgslam::data
