#pragma once
// TUM trajectory files: one pose per line, "timestamp tx ty tz qx qy qz qw", camera-to-world
// (T_wc), timestamps in seconds, translation in metres, unit quaternion (x, y, z, w).
#include <iosfwd>
#include <string>
#include <vector>

#include "tkgslam/common/Pose.h"

namespace tkgslam::io {

/// One raw trajectory line. The quaternion is kept as read (the TUM RPE script skips lines whose
/// quaternion is all zero while its ATE script keeps them, so the evaluator needs the raw value).
struct TrajectoryEntry {
  double timestamp = 0.0;
  Vec3 t = Vec3::Zero();
  Eigen::Vector4d q_xyzw = Eigen::Vector4d(0, 0, 0, 1);

  bool hasZeroQuaternion() const { return q_xyzw.isZero(0.0); }
  Pose pose() const;
};

/// Parses a TUM trajectory. Comment ('#') and blank lines are skipped; separators may be spaces,
/// tabs or commas. Entries are returned sorted by timestamp; for a repeated timestamp the last
/// line wins (as in the TUM scripts). Throws InputError naming `source` and the line number on a
/// malformed line (fewer than 8 fields, non-numeric or non-finite values).
std::vector<TrajectoryEntry> parseTumTrajectory(std::istream& in, const std::string& source);

/// Reads a TUM trajectory file; throws InputError if it cannot be opened or is malformed.
std::vector<TrajectoryEntry> readTumTrajectory(const std::string& path);

/// One pose as a line of a TUM trajectory, without the newline: 6-decimal timestamp, 9-decimal
/// values, a unit quaternion with qw >= 0.
std::string formatTumPose(const StampedPose& pose);

/// Writes poses in TUM format (lines of formatTumPose under a header). Throws InputError if the
/// file cannot be written.
void writeTumTrajectory(const std::string& path, const std::vector<StampedPose>& poses);

/// Poses as the entries a written and re-read trajectory would give (unit quaternions, qw >= 0),
/// to score them (eval::computeAte) without a file.
std::vector<TrajectoryEntry> toTrajectoryEntries(const std::vector<StampedPose>& poses);

}  // namespace tkgslam::io
