#include "tkgslam/io/TrajectoryFile.h"

#include <algorithm>
#include <fstream>
#include <map>

#include <fmt/format.h>

#include "tkgslam/common/Error.h"
#include "tkgslam/io/TextParsing.h"
#include "tkgslam/io/InputFile.h"
#include "tkgslam/io/OutputFile.h"

namespace tkgslam::io {

Pose TrajectoryEntry::pose() const {
  return poseFromTranslationQuaternion(t, q_xyzw[0], q_xyzw[1], q_xyzw[2], q_xyzw[3]);
}

std::vector<TrajectoryEntry> parseTumTrajectory(std::istream& in, const std::string& source) {
  std::map<double, TrajectoryEntry> by_time;
  std::string line;
  int line_no = 0;
  skipByteOrderMark(in);
  while (std::getline(in, line)) {
    ++line_no;
    if (isCommentOrBlank(line)) continue;
    const auto fields = splitFields(line);
    if (fields.size() < 8) {
      throw InputError(fmt::format("{}:{}: expected 8 values 'timestamp tx ty tz qx qy qz qw', got {}",
                                   source, line_no, fields.size()));
    }
    double v[8];
    for (int i = 0; i < 8; ++i) {
      if (!parseDouble(fields[i], v[i])) {
        throw InputError(fmt::format("{}:{}: value {} ('{}') is not a finite number", source,
                                     line_no, i + 1, fields[i]));
      }
    }
    TrajectoryEntry e;
    e.timestamp = v[0];
    e.t = Vec3(v[1], v[2], v[3]);
    e.q_xyzw = Eigen::Vector4d(v[4], v[5], v[6], v[7]);
    by_time[e.timestamp] = e;
  }
  std::vector<TrajectoryEntry> out;
  out.reserve(by_time.size());
  for (auto& kv : by_time) out.push_back(kv.second);
  return out;
}

std::vector<TrajectoryEntry> readTumTrajectory(const std::string& path) {
  std::ifstream in = openInputFile(path, "trajectory file");
  return parseTumTrajectory(in, path);
}

namespace {

/// The rotation as written: unit, qw >= 0 (q and -q are the same rotation).
Eigen::Quaterniond writtenQuaternion(const Pose& T_wc) {
  Eigen::Quaterniond q(T_wc.linear());
  q.normalize();
  if (q.w() < 0) q.coeffs() *= -1.0;
  return q;
}

}  // namespace

std::string formatTumPose(const StampedPose& pose) {
  const Eigen::Quaterniond q = writtenQuaternion(pose.T_wc);
  const Vec3 t = pose.T_wc.translation();
  return fmt::format("{:.6f} {:.9f} {:.9f} {:.9f} {:.9f} {:.9f} {:.9f} {:.9f}", pose.timestamp, t.x(), t.y(), t.z(),
                     q.x(), q.y(), q.z(), q.w());
}

void writeTumTrajectory(const std::string& path, const std::vector<StampedPose>& poses) {
  std::string text = "# timestamp tx ty tz qx qy qz qw (camera-to-world, metres)\n";
  for (const auto& p : poses) text += formatTumPose(p) + "\n";
  writeOutputFile(path, "trajectory file", text);
}

std::vector<TrajectoryEntry> toTrajectoryEntries(const std::vector<StampedPose>& poses) {
  std::vector<TrajectoryEntry> entries;
  entries.reserve(poses.size());
  for (const auto& p : poses) {
    TrajectoryEntry e;
    e.timestamp = p.timestamp;
    e.t = p.T_wc.translation();
    e.q_xyzw = writtenQuaternion(p.T_wc).coeffs();  // Eigen stores x, y, z, w
    entries.push_back(e);
  }
  return entries;
}

}  // namespace tkgslam::io
