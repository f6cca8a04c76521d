#pragma once
// A keyframe of real features at a given pose with a map point for every keypoint with depth
// (observed by that keyframe only), added to a map: the makings of a map for loop-closing tests
// and benchmarks. Header-only (used by tests/ and bench/).
#include <memory>

#include "tkgslam/camera/PinholeCamera.h"
#include "tkgslam/data/FrameFeatures.h"
#include "tkgslam/data/KeyFrame.h"
#include "tkgslam/data/Map.h"
#include "tkgslam/data/MapPoint.h"
#include "tkgslam/feature/ScalePyramid.h"

namespace tkgslam::test {

inline std::shared_ptr<data::KeyFrame> addKeyFrameWithPoints(data::Map& map,
                                                             const std::shared_ptr<data::FrameFeatures>& features,
                                                             long frame_id, double timestamp, const Pose& T_cw,
                                                             const camera::PinholeCamera& camera,
                                                             const feature::ScalePyramid& pyramid) {
  auto kf = std::make_shared<data::KeyFrame>(map.newKeyFrameId(), frame_id, timestamp, features, T_cw);
  for (int k = 0; k < features->size(); ++k) {
    if (!features->hasDepth(k)) continue;
    const Vec3 pw =
        kf->T_wc() * camera.unproject(Vec2(features->ideal[k].pt.x, features->ideal[k].pt.y), features->depth[k]);
    auto mp = std::make_shared<data::MapPoint>(map.newMapPointId(), pw, kf.get(), features->descriptors.row(k));
    mp->observations[kf.get()] = k;
    kf->addMapPoint(mp, k);
    map.addMapPoint(mp);
    mp->updateNormalAndDepth(pyramid);
  }
  map.addKeyFrame(kf);
  return kf;
}

}  // namespace tkgslam::test
