// Map files: what is saved comes back, and what is not a map file is refused - never a crash.
#include <cstring>

#include <gtest/gtest.h>

#include "TestSupport.h"
#include "tkgslam/common/Error.h"
#include "tkgslam/io/ConfigFile.h"
#include "tkgslam/io/MapFile.h"
#include "tkgslam/system/SlamSystem.h"

namespace tkgslam {
namespace {

/// A real map: 40 frames of fr1_xyz (orb mode, deterministic), saved; with the config it was made with.
struct SavedMap {
  SlamConfig config;
  std::string bytes;
  size_t keyframes = 0, points = 0;
  std::vector<StampedPose> keyframe_poses;
};

const SavedMap& savedMap() {
  static const SavedMap saved = [] {
    SavedMap s;
    s.config = io::loadConfig((test::sourceDir() / "configs" / "tum_fr1.yaml").string());
    s.config.deterministic = true;
    s.config.dynamic.mode = DynamicMode::Orb;
    io::TumDatasetOptions dopt;
    dopt.depth_factor = s.config.depth.factor;
    io::TumDataset dataset(test::fr1xyz().string(), dopt);
    SlamSystem slam(s.config);
    for (int i = 0; i < 40; ++i) slam.processFrame(dataset.load(i));
    slam.finish();
    test::TempDir tmp;
    slam.saveMap((tmp / "map.tkgmap").string());
    s.bytes = test::readFile(tmp / "map.tkgmap");
    s.keyframes = slam.keyFrameCount();
    s.points = slam.mapPointCount();
    s.keyframe_poses = slam.keyFrameTrajectory();
    return s;
  }();
  return saved;
}

struct CameraAndPyramid {
  camera::PinholeCamera camera;
  feature::ScalePyramid pyramid;
  explicit CameraAndPyramid(const SlamConfig& c)
      : camera(c.camera), pyramid(feature::ScalePyramid::make(c.orb.levels, c.orb.scale_factor)) {}
};

TEST(MapFile, ASavedMapReadsBackWithItsKeyframesPointsAndLinks) {
  TKGSLAM_REQUIRE_SHARED();
  const auto& saved = savedMap();
  ASSERT_GE(saved.keyframes, 3u);
  ASSERT_GE(saved.points, 500u);
  const CameraAndPyramid cp(saved.config);
  data::Map map;
  ASSERT_EQ(io::deserializeMap(saved.bytes, map, cp.camera, cp.pyramid), saved.keyframes);
  EXPECT_EQ(map.keyFrameCount(), saved.keyframes);
  EXPECT_EQ(map.mapPointCount(), saved.points);

  const auto kfs = map.keyFrames();
  ASSERT_EQ(kfs.size(), saved.keyframe_poses.size());
  for (size_t k = 0; k < kfs.size(); ++k) {
    EXPECT_EQ(kfs[k]->timestamp, saved.keyframe_poses[k].timestamp);
    EXPECT_TRUE(kfs[k]->T_wc().matrix() == saved.keyframe_poses[k].T_wc.matrix()) << "keyframe " << k;
    // Frames of an earlier run: negative, in order, the last -1.
    EXPECT_LT(kfs[k]->frame_id, 0);
    if (k > 0) {
      EXPECT_GT(kfs[k]->frame_id, kfs[k - 1]->frame_id);
    }
    EXPECT_GT(kfs[k]->features->size(), 500);
    // Links rebuilt: every keyframe after the first shares points with another and has a parent.
    EXPECT_FALSE(kfs[k]->connections.empty()) << "keyframe " << k;
    if (k > 0) {
      EXPECT_NE(kfs[k]->parent, nullptr) << "keyframe " << k;
    }
  }
  EXPECT_EQ(kfs.back()->frame_id, -1);
  // Every point is in the slots of the keyframes that observe it, and the grid finds its keypoints.
  for (const auto& mp : map.mapPoints()) {
    ASSERT_FALSE(mp->observations.empty());
    for (const auto& [kf, idx] : mp->observations) {
      ASSERT_EQ(kf->map_points.at(idx).get(), mp.get());
      const auto& kp = kf->features->ideal[idx].pt;
      const auto near = kf->features->featuresInArea(kp.x, kp.y, 1.0f);
      EXPECT_NE(std::find(near.begin(), near.end(), idx), near.end());
    }
  }
  // New ids continue after the loaded ones.
  EXPECT_GT(map.newKeyFrameId(), kfs.back()->id);

  // Written again, read again: the same bytes (only the frame ids changed on the first read).
  const std::string again = io::serializeMap(map, cp.camera, cp.pyramid);
  EXPECT_EQ(again.size(), saved.bytes.size());
  data::Map map2;
  io::deserializeMap(again, map2, cp.camera, cp.pyramid);
  EXPECT_EQ(io::serializeMap(map2, cp.camera, cp.pyramid), again);
}

TEST(MapFile, EveryTruncationIsRefusedAndLeavesTheMapEmpty) {
  TKGSLAM_REQUIRE_SHARED();
  const auto& saved = savedMap();
  const CameraAndPyramid cp(saved.config);
  int refused = 0;
  for (size_t len = 0; len < saved.bytes.size(); len += len < 4096 ? 1 : 4093) {
    data::Map map;
    try {
      io::deserializeMap(std::string_view(saved.bytes).substr(0, len), map, cp.camera, cp.pyramid);
      ADD_FAILURE() << "a map cut at byte " << len << " was accepted";
    } catch (const InputError& e) {
      ++refused;
      EXPECT_NE(std::string(e.what()).find("not a valid map file"), std::string::npos) << e.what();
    }
    ASSERT_EQ(map.keyFrameCount() + map.mapPointCount(), 0u) << len;
  }
  EXPECT_GT(refused, 4096);
  // Bytes after the end are refused too.
  data::Map map;
  EXPECT_THROW(io::deserializeMap(saved.bytes + "x", map, cp.camera, cp.pyramid), InputError);
}

TEST(MapFile, CorruptedBytesAreRefusedOrGiveAConsistentMap) {
  TKGSLAM_REQUIRE_SHARED();
  const auto& saved = savedMap();
  const CameraAndPyramid cp(saved.config);
  int refused = 0, loaded = 0;
  // Every byte of the header and the first keyframe's record and keypoints; then anywhere.
  for (size_t pos = 0; pos < saved.bytes.size(); pos += pos < 400 ? 1 : 1999) {
    for (unsigned char flip : {0x80, 0xff}) {
      std::string bytes = saved.bytes;
      bytes[pos] = char(bytes[pos] ^ flip);
      data::Map map;
      try {
        io::deserializeMap(bytes, map, cp.camera, cp.pyramid);
        ++loaded;
        for (const auto& mp : map.mapPoints()) {
          for (const auto& [kf, idx] : mp->observations) ASSERT_EQ(kf->map_points.at(idx).get(), mp.get());
        }
      } catch (const InputError&) {
        ++refused;
        ASSERT_EQ(map.keyFrameCount() + map.mapPointCount(), 0u);
      }
    }
  }
  // Most single flips in descriptors, colours or positions are harmless values; the header's are not.
  EXPECT_GT(refused, 100);
  EXPECT_GT(loaded, 100);
}

TEST(MapFile, AnotherCameraPyramidOrVersionIsRefusedSayingWhy) {
  TKGSLAM_REQUIRE_SHARED();
  const auto& saved = savedMap();
  const auto refusal = [&](const SlamConfig& config, const std::string& bytes) {
    const CameraAndPyramid cp(config);
    data::Map map;
    try {
      io::deserializeMap(bytes, map, cp.camera, cp.pyramid);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  SlamConfig other = saved.config;
  other.camera.fx += 1.0;
  EXPECT_NE(refusal(other, saved.bytes).find("the map was built with another camera"), std::string::npos);
  other = saved.config;
  other.orb.levels = 4;
  EXPECT_NE(refusal(other, saved.bytes).find("another ORB pyramid (8 levels"), std::string::npos);
  std::string v2 = saved.bytes;
  v2[12] = 2;  // the version follows the 12-byte marker
  EXPECT_NE(refusal(saved.config, v2).find("format version 2 is not the one this build reads (1)"), std::string::npos);
  EXPECT_NE(refusal(saved.config, "not a map").find("not a valid map file"), std::string::npos);

  // Only into an empty map.
  const CameraAndPyramid cp(saved.config);
  data::Map map;
  io::deserializeMap(saved.bytes, map, cp.camera, cp.pyramid);
  EXPECT_THROW(io::deserializeMap(saved.bytes, map, cp.camera, cp.pyramid), InputError);
  EXPECT_EQ(map.keyFrameCount(), saved.keyframes);
}

TEST(MapFile, AParentThatIsNotAnOlderKeyframeIsRefused) {
  TKGSLAM_REQUIRE_SHARED();
  const auto& saved = savedMap();
  const CameraAndPyramid cp(saved.config);
  // The first keyframe's record starts at byte 80 (marker, version, byte order, camera and pyramid,
  // keyframe count); its parent follows id, frame id, timestamp, pose and flags, at byte 201.
  constexpr size_t kFirstKeyFrame = 80, kParent = kFirstKeyFrame + 8 + 8 + 8 + 96 + 1;
  int64_t id;
  std::memcpy(&id, saved.bytes.data() + kFirstKeyFrame, 8);
  std::string bytes = saved.bytes;
  std::memcpy(bytes.data() + kParent, &id, 8);  // its own parent: walking up the tree would not end
  data::Map map;
  try {
    io::deserializeMap(bytes, map, cp.camera, cp.pyramid);
    ADD_FAILURE() << "a keyframe that is its own parent was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("has parent " + std::to_string(id) + ", not an older keyframe"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace tkgslam
