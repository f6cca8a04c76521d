#include "tkgslam/io/MapFile.h"

#include <cmath>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>
#include <type_traits>

#include <fmt/format.h>

#include "tkgslam/common/Error.h"
#include "tkgslam/io/InputFile.h"
#include "tkgslam/io/OutputFile.h"

namespace tkgslam::io {

namespace {

constexpr char kMagic[12] = {'T', 'K', 'G', 'S', 'L', 'A', 'M', '-', 'M', 'A', 'P', '\0'};
constexpr uint32_t kByteOrder = 0x01020304;  // read back as another value on a big-endian machine
constexpr char kEnd[4] = {'E', 'N', 'D', '\0'};
constexpr int kDescriptorBytes = 32;
// Ids and counts are bounded far beyond any map, so that arithmetic on them cannot overflow.
constexpr int64_t kMaxId = int64_t(1) << 40;
constexpr int32_t kMaxCount = 1 << 30;

class ByteWriter {
 public:
  template <typename T>
  void put(T v) {
    static_assert(std::is_trivially_copyable_v<T>);
    bytes_.append(reinterpret_cast<const char*>(&v), sizeof(T));
  }
  void putBytes(const void* p, size_t n) { bytes_.append(static_cast<const char*>(p), n); }
  void putPose(const Pose& T) {
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 4; ++c) put<double>(T.matrix()(r, c));
    }
  }
  std::string take() { return std::move(bytes_); }

 private:
  std::string bytes_;
};

/// Bounds-checked reading; every failure is an InputError naming the field.
class ByteReader {
 public:
  explicit ByteReader(std::string_view bytes) : bytes_(bytes) {}

  template <typename T>
  T get(const char* what) {
    static_assert(std::is_trivially_copyable_v<T>);
    need(sizeof(T), what);
    T v;
    std::memcpy(&v, bytes_.data() + pos_, sizeof(T));
    pos_ += sizeof(T);
    if constexpr (std::is_floating_point_v<T>) {
      if (!std::isfinite(v)) fail(fmt::format("{} is not a finite number", what));
    }
    return v;
  }
  void getBytes(void* p, size_t n, const char* what) {
    need(n, what);
    std::memcpy(p, bytes_.data() + pos_, n);
    pos_ += n;
  }
  Pose getPose(const char* what) {
    Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 4; ++c) m(r, c) = get<double>(what);
    }
    const Eigen::Matrix3d R = m.topLeftCorner<3, 3>();
    if ((R * R.transpose() - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff() > 1e-6 || R.determinant() < 0) {
      fail(fmt::format("{} is not a rigid transform", what));
    }
    Pose T;
    T.matrix() = m;
    return T;
  }
  /// A count of records of at least `record_bytes` each: refused before anything is allocated if
  /// the rest of the file cannot hold them.
  /// An id in [lo, kMaxId).
  int64_t getId(const char* what, int64_t lo = 0) {
    const auto v = get<int64_t>(what);
    if (v < lo || v >= kMaxId) fail(fmt::format("{} {} is out of range", what, v));
    return v;
  }
  uint64_t getCount(size_t record_bytes, const char* what) {
    const auto n = get<uint64_t>(what);
    if (n > remaining() / record_bytes) fail(fmt::format("{} ({}) is more than the file holds", what, n));
    return n;
  }
  size_t remaining() const { return bytes_.size() - pos_; }
  size_t position() const { return pos_; }
  [[noreturn]] void fail(const std::string& why) const {
    throw InputError(fmt::format("not a valid map file: {} (at byte {})", why, pos_));
  }

 private:
  void need(size_t n, const char* what) const {
    if (remaining() < n) fail(fmt::format("truncated: ends in the middle of {}", what));
  }
  std::string_view bytes_;
  size_t pos_ = 0;
};

// Fixed sizes of the records, for the counts' plausibility checks.
constexpr size_t kKeypointBytes = 7 * 4 + 2 * 4 + 2 * 4 + 1 + 3 + kDescriptorBytes;
constexpr size_t kKeyFrameBytes = 8 + 8 + 8 + 12 * 8 + 1 + 8 + 8 + 4;
constexpr size_t kObservationBytes = 8 + 4;
constexpr size_t kMapPointBytes = 8 + 3 * 8 + kDescriptorBytes + 3 * 8 + 2 * 4 + 8 + 8 + 2 * 4 + 8;

void writeCompatibility(ByteWriter& w, const camera::PinholeCamera& camera, const feature::ScalePyramid& pyr) {
  w.put<int32_t>(camera.width());
  w.put<int32_t>(camera.height());
  w.put<double>(camera.fx());
  w.put<double>(camera.fy());
  w.put<double>(camera.cx());
  w.put<double>(camera.cy());
  w.put<int32_t>(pyr.levels);
  w.put<double>(pyr.scale_factor);
}

void checkCompatibility(ByteReader& r, const camera::PinholeCamera& camera, const feature::ScalePyramid& pyr) {
  const auto width = r.get<int32_t>("image width");
  const auto height = r.get<int32_t>("image height");
  const auto fx = r.get<double>("fx"), fy = r.get<double>("fy"), cx = r.get<double>("cx"), cy = r.get<double>("cy");
  const auto levels = r.get<int32_t>("pyramid levels");
  const auto scale = r.get<double>("pyramid scale factor");
  const auto close = [](double a, double b) { return std::abs(a - b) <= 1e-9 * std::max(1.0, std::abs(b)); };
  if (width != camera.width() || height != camera.height() || !close(fx, camera.fx()) || !close(fy, camera.fy()) ||
      !close(cx, camera.cx()) || !close(cy, camera.cy())) {
    throw InputError(fmt::format(
        "the map was built with another camera ({}x{}, fx {} fy {} cx {} cy {}) than the config's ({}x{}, fx {} fy {} "
        "cx {} cy {}): keypoint positions would not match",
        width, height, fx, fy, cx, cy, camera.width(), camera.height(), camera.fx(), camera.fy(), camera.cx(),
        camera.cy()));
  }
  if (levels != pyr.levels || !close(scale, pyr.scale_factor)) {
    throw InputError(fmt::format("the map was built with another ORB pyramid ({} levels, scale {}) than the config's "
                                 "({} levels, scale {}): keypoint scales would not match",
                                 levels, scale, pyr.levels, pyr.scale_factor));
  }
}

void writeKeyFrame(ByteWriter& w, const data::KeyFrame& kf) {
  const auto& F = *kf.features;
  w.put<int64_t>(kf.id);
  w.put<int64_t>(kf.frame_id);
  w.put<double>(kf.timestamp);
  w.putPose(kf.T_cw());
  w.put<uint8_t>(kf.not_erase);
  w.put<int64_t>(kf.parent && !kf.parent->bad ? kf.parent->id : -1);
  w.put<double>(F.sharpness);
  w.put<uint32_t>(F.size());
  for (int i = 0; i < F.size(); ++i) {
    const auto& k = F.raw[i];
    w.put<float>(k.pt.x);
    w.put<float>(k.pt.y);
    w.put<float>(k.size);
    w.put<float>(k.angle);
    w.put<float>(k.response);
    w.put<int32_t>(k.octave);
    w.put<int32_t>(k.class_id);
    w.put<float>(F.ideal[i].pt.x);
    w.put<float>(F.ideal[i].pt.y);
    w.put<float>(F.depth[i]);
    w.put<float>(F.u_right[i]);
    w.put<uint8_t>(F.excluded[i]);
    w.putBytes(&F.colour[i], 3);
  }
  w.putBytes(F.descriptors.data, size_t(F.size()) * kDescriptorBytes);
}

/// A keyframe as read, before it becomes a KeyFrame (whose frame id is fixed at construction).
struct KeyFrameRecord {
  long id = 0, frame_id = 0, parent = -1;
  double timestamp = 0;
  Pose T_cw;
  bool not_erase = false;
  std::shared_ptr<data::FrameFeatures> features;
};

KeyFrameRecord readKeyFrame(ByteReader& r, const camera::PinholeCamera& camera, const feature::ScalePyramid& pyr) {
  KeyFrameRecord kf;
  kf.id = r.getId("keyframe id");
  kf.frame_id = r.getId("keyframe frame id", -kMaxId);
  kf.timestamp = r.get<double>("keyframe timestamp");
  kf.T_cw = r.getPose("keyframe pose");
  if (kf.T_cw.translation().cwiseAbs().maxCoeff() > 1e6) r.fail(fmt::format("keyframe {} lies too far away", kf.id));
  kf.not_erase = r.get<uint8_t>("keyframe flags") != 0;
  kf.parent = r.getId("keyframe parent", -1);
  // The spanning tree points to older keyframes only (so walking up it ends).
  if (kf.parent >= kf.id) r.fail(fmt::format("keyframe {} has parent {}, not an older keyframe", kf.id, kf.parent));
  auto F = std::make_shared<data::FrameFeatures>();
  F->sharpness = r.get<double>("keyframe sharpness");
  const auto n = r.get<uint32_t>("keypoint count");
  if (n > r.remaining() / kKeypointBytes) r.fail(fmt::format("keypoint count ({}) is more than the file holds", n));
  F->raw.resize(n);
  F->ideal.resize(n);
  F->depth.resize(n);
  F->u_right.resize(n);
  F->excluded.resize(n);
  F->colour.resize(n);
  for (uint32_t i = 0; i < n; ++i) {
    auto& k = F->raw[i];
    k.pt.x = r.get<float>("keypoint x");
    k.pt.y = r.get<float>("keypoint y");
    k.size = r.get<float>("keypoint size");
    k.angle = r.get<float>("keypoint angle");
    k.response = r.get<float>("keypoint response");
    k.octave = r.get<int32_t>("keypoint octave");
    if (k.octave < 0 || k.octave >= pyr.levels) {
      r.fail(fmt::format("keypoint octave {} is outside the pyramid's {} levels", k.octave, pyr.levels));
    }
    k.class_id = r.get<int32_t>("keypoint class");
    F->ideal[i] = k;
    F->ideal[i].pt.x = r.get<float>("keypoint ideal x");
    F->ideal[i].pt.y = r.get<float>("keypoint ideal y");
    F->depth[i] = r.get<float>("keypoint depth");
    F->u_right[i] = r.get<float>("keypoint right u");
    // Pixel positions far off the image would overflow the grid's cell arithmetic.
    const float limit = 10.0f * float(std::max(camera.width(), camera.height()));
    for (float v : {k.pt.x, k.pt.y, F->ideal[i].pt.x, F->ideal[i].pt.y, F->u_right[i]}) {
      if (std::abs(v) > limit) r.fail(fmt::format("keypoint position {} is far outside the image", v));
    }
    if (F->depth[i] < 0) r.fail(fmt::format("keypoint depth {} is negative", F->depth[i]));
    F->excluded[i] = r.get<uint8_t>("keypoint flags") != 0;
    r.getBytes(&F->colour[i], 3, "keypoint colour");
  }
  F->descriptors.create(int(n), kDescriptorBytes, CV_8U);
  if (n > 0) r.getBytes(F->descriptors.data, size_t(n) * kDescriptorBytes, "descriptors");
  data::indexFeatures(*F, camera);
  kf.features = std::move(F);
  return kf;
}

void writeMapPoint(ByteWriter& w, const data::MapPoint& mp) {
  w.put<int64_t>(mp.id);
  for (int k = 0; k < 3; ++k) w.put<double>(mp.pos_w[k]);
  w.putBytes(mp.descriptor.data, kDescriptorBytes);
  for (int k = 0; k < 3; ++k) w.put<double>(mp.normal[k]);
  w.put<float>(mp.min_distance);
  w.put<float>(mp.max_distance);
  w.put<int64_t>(mp.reference ? mp.reference->id : -1);
  w.put<int64_t>(mp.first_keyframe_id);
  w.put<int32_t>(mp.visible);
  w.put<int32_t>(mp.found);
  w.put<uint64_t>(mp.observations.size());
  for (const auto& [kf, idx] : mp.observations) {
    w.put<int64_t>(kf->id);
    w.put<uint32_t>(idx);
  }
}

/// Reads a point and links it into its keyframes (`keyframes` by id; their slots must be free).
std::shared_ptr<data::MapPoint> readMapPoint(ByteReader& r,
                                             const std::map<long, std::shared_ptr<data::KeyFrame>>& keyframes) {
  const auto id = r.getId("point id");
  Vec3 pos;
  for (int k = 0; k < 3; ++k) pos[k] = r.get<double>("point position");
  // (Projections of points that far would overflow pixel arithmetic.)
  if (pos.cwiseAbs().maxCoeff() > 1e6) r.fail(fmt::format("point {} lies {} m away", id, pos.norm()));
  cv::Mat descriptor(1, kDescriptorBytes, CV_8U);
  r.getBytes(descriptor.data, kDescriptorBytes, "point descriptor");
  auto mp = std::make_shared<data::MapPoint>(id, pos, nullptr, descriptor);
  for (int k = 0; k < 3; ++k) mp->normal[k] = r.get<double>("point normal");
  mp->min_distance = r.get<float>("point distance range");
  mp->max_distance = r.get<float>("point distance range");
  if (!(mp->min_distance > 0 && mp->max_distance >= mp->min_distance)) {
    r.fail(fmt::format("point {} has distance range {} - {} m", id, mp->min_distance, mp->max_distance));
  }
  const auto reference = r.getId("point reference keyframe", -1);
  mp->first_keyframe_id = r.getId("point first keyframe");
  mp->visible = r.get<int32_t>("point visible count");
  mp->found = r.get<int32_t>("point found count");
  if (mp->visible < 1 || mp->found < 0 || mp->visible >= kMaxCount || mp->found >= kMaxCount) {
    r.fail(fmt::format("point {} has counts {} / {}", id, mp->found, mp->visible));
  }
  const auto n = r.getCount(kObservationBytes, "observation count");
  if (n == 0) r.fail(fmt::format("point {} has no observation", id));
  for (uint64_t k = 0; k < n; ++k) {
    const auto kf_id = r.getId("observation keyframe");
    const auto idx = r.get<uint32_t>("observation keypoint");
    const auto it = keyframes.find(kf_id);
    if (it == keyframes.end()) r.fail(fmt::format("point {} is seen by keyframe {}, which is not in the file", id, kf_id));
    auto& kf = *it->second;
    if (idx >= kf.map_points.size()) {
      r.fail(fmt::format("point {} is keypoint {} of keyframe {}, which has {}", id, idx, kf_id, kf.map_points.size()));
    }
    if (kf.map_points[idx] || mp->observations.count(&kf)) {
      r.fail(fmt::format("keypoint {} of keyframe {} is given two points", idx, kf_id));
    }
    kf.map_points[idx] = mp;
    mp->observations[&kf] = int(idx);
  }
  const auto ref = keyframes.find(reference);
  mp->reference = ref != keyframes.end() && mp->observations.count(ref->second.get()) ? ref->second.get()
                                                                                       : mp->observations.begin()->first;
  return mp;
}

}  // namespace

std::string serializeMap(const data::Map& map, const camera::PinholeCamera& camera, const feature::ScalePyramid& pyramid) {
  ByteWriter w;
  w.putBytes(kMagic, sizeof(kMagic));
  w.put<uint32_t>(kMapFileVersion);
  w.put<uint32_t>(kByteOrder);
  writeCompatibility(w, camera, pyramid);
  const auto keyframes = map.keyFrames();
  w.put<uint64_t>(keyframes.size());
  for (const auto& kf : keyframes) writeKeyFrame(w, *kf);
  // Only points whose observers are all saved (an active point is seen by active keyframes only).
  const auto points = map.mapPoints();
  std::vector<const data::MapPoint*> saved;
  for (const auto& mp : points) {
    bool ok = !mp->bad && !mp->observations.empty();
    for (const auto& [kf, idx] : mp->observations) ok = ok && !kf->bad && kf->features;
    if (ok) saved.push_back(mp.get());
  }
  w.put<uint64_t>(saved.size());
  for (const auto* mp : saved) writeMapPoint(w, *mp);
  w.putBytes(kEnd, sizeof(kEnd));
  return w.take();
}

size_t deserializeMap(std::string_view bytes, data::Map& map, const camera::PinholeCamera& camera,
                      const feature::ScalePyramid& pyramid) {
  if (map.keyFrameCount() > 0 || map.mapPointCount() > 0) throw InputError("a map file can only be read into an empty map");
  ByteReader r(bytes);
  char magic[sizeof(kMagic)];
  r.getBytes(magic, sizeof(magic), "the file type marker");
  if (std::memcmp(magic, kMagic, sizeof(kMagic)) != 0) r.fail("it does not start with the TKGSLAM-MAP marker");
  const auto version = r.get<uint32_t>("the format version");
  if (version != kMapFileVersion) {
    throw InputError(fmt::format("map file format version {} is not the one this build reads ({})", version,
                                 kMapFileVersion));
  }
  if (r.get<uint32_t>("the byte order mark") != kByteOrder) r.fail("it was written with another byte order");
  checkCompatibility(r, camera, pyramid);

  // Everything is read and checked before the map is touched.
  std::vector<KeyFrameRecord> records;
  const auto n_kf = r.getCount(kKeyFrameBytes, "keyframe count");
  for (uint64_t k = 0; k < n_kf; ++k) records.push_back(readKeyFrame(r, camera, pyramid));
  // Frames of an earlier run: negative frame ids keep their order and never meet this run's.
  long last_frame = records.empty() ? 0 : records.front().frame_id;
  for (const auto& rec : records) last_frame = std::max(last_frame, rec.frame_id);
  // Rebased, the frame ids must still be ones a map file may hold (so a saved map reads back).
  for (const auto& rec : records) {
    if (rec.frame_id - last_frame - 1 < -kMaxId) r.fail("keyframe frame ids span more than 2^40 frames");
  }
  std::map<long, std::shared_ptr<data::KeyFrame>> keyframes;
  for (auto& rec : records) {
    auto kf = std::make_shared<data::KeyFrame>(rec.id, rec.frame_id - last_frame - 1, rec.timestamp,
                                               std::move(rec.features), rec.T_cw);
    kf->not_erase = rec.not_erase;
    if (!keyframes.emplace(kf->id, kf).second) r.fail(fmt::format("keyframe id {} appears twice", kf->id));
  }
  std::map<long, std::shared_ptr<data::MapPoint>> points;
  const auto n_mp = r.getCount(kMapPointBytes, "point count");
  for (uint64_t k = 0; k < n_mp; ++k) {
    auto mp = readMapPoint(r, keyframes);
    if (!points.emplace(mp->id, mp).second) r.fail(fmt::format("point id {} appears twice", mp->id));
  }
  char end[sizeof(kEnd)];
  r.getBytes(end, sizeof(end), "the end marker");
  if (std::memcmp(end, kEnd, sizeof(kEnd)) != 0 || r.remaining() != 0) r.fail("no end marker where the map ends");

  for (const auto& rec : records) {
    const auto parent = keyframes.find(rec.parent);
    if (parent == keyframes.end()) continue;
    auto& kf = *keyframes.at(rec.id);
    kf.parent = parent->second.get();
    parent->second->children.insert(&kf);
  }
  for (const auto& [id, kf] : keyframes) map.addKeyFrame(kf);
  for (const auto& [id, mp] : points) map.addMapPoint(mp);
  for (const auto& [id, kf] : keyframes) kf->updateConnections();
  map.continueIdsAfter(keyframes.empty() ? -1 : keyframes.rbegin()->first,
                       points.empty() ? -1 : points.rbegin()->first);
  return keyframes.size();
}

void writeMapFile(const std::string& path, const data::Map& map, const camera::PinholeCamera& camera,
                  const feature::ScalePyramid& pyramid) {
  const std::string bytes = serializeMap(map, camera, pyramid);
  writeOutputFile(path, "map file", bytes);
}

size_t readMapFile(const std::string& path, data::Map& map, const camera::PinholeCamera& camera,
                   const feature::ScalePyramid& pyramid) {
  std::ifstream in = openInputFile(path, "map file", std::ios::binary);
  std::ostringstream buf;
  buf << in.rdbuf();
  try {
    return deserializeMap(buf.str(), map, camera, pyramid);
  } catch (const InputError& e) {
    throw InputError(fmt::format("{}: {}", path, e.what()));
  }
}

}  // namespace tkgslam::io
