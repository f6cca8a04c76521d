#pragma once
// Reader for RGB-D sequences in the TUM benchmark layout:
//   DIR/rgb.txt, DIR/depth.txt   "timestamp filename" lists ('#' comments), names relative to DIR
//   DIR/groundtruth.txt          optional, TUM trajectory
// RGB and depth are associated with the TUM rule (|t_rgb - t_depth| < 0.02 s, greedy by smallest
// difference). Or the pairs come from an association file as ORB-SLAM2's RGB-D example reads it
// ("timestamp file timestamp file" per line, as the TUM tools' associate.py writes it): the pairs
// as listed, names relative to DIR, either column order (associate.py writes the list it is given
// first in the first column; the 16-bit single-channel image of the first pair is the depth).
// Images are loaded lazily, one frame at a time.
#include <optional>
#include <string>
#include <vector>

#include <opencv2/core.hpp>

namespace tkgslam::io {

struct TumDatasetOptions {
  double depth_factor = 5000.0;        ///< raw depth units per metre (TUM: 5000)
  double max_time_difference = 0.02;   ///< association window, seconds
  int expected_width = 0;              ///< 0 = accept any size; otherwise images must match
  int expected_height = 0;
  int loops = 1;                       ///< repeat the sequence (soak tests); stamps keep increasing
  /// An association file to take the pairs from instead of rgb.txt and depth.txt (empty: the lists).
  std::string associations;
};

/// One associated RGB-D pair as listed (paths absolute or relative to the working directory).
struct RgbdEntry {
  double rgb_timestamp = 0.0;  ///< seconds; the frame's timestamp
  double depth_timestamp = 0.0;
  std::string rgb_path;
  std::string depth_path;
};

/// A loaded frame: BGR 8-bit colour, grey 8-bit, and depth in metres (CV_32F, 0 = no depth).
struct RgbdImages {
  double timestamp = 0.0;
  cv::Mat bgr;
  cv::Mat gray;
  cv::Mat depth_m;
  cv::Mat truth_mask;  ///< composites only: 255 where a dynamic object really is (else empty)
};

/// One "timestamp filename" line of rgb.txt / depth.txt.
struct ListEntry {
  double timestamp = 0.0;
  std::string file;
};

/// Parses a TUM image list from text. Throws InputError naming `source` and the line for a
/// malformed or non-increasing timestamp or a missing file name.
std::vector<ListEntry> parseTumImageList(std::istream& in, const std::string& source);

/// One line of an association file: two "timestamp filename" pairs, in the file's order.
struct AssociationLine {
  ListEntry first;
  ListEntry second;
  int line = 0;  ///< in the file, from 1
};

/// Parses an association file from text. Throws InputError naming `source` and the line for a
/// line without four fields, a malformed timestamp, or a first timestamp not after the previous.
std::vector<AssociationLine> parseAssociationFile(std::istream& in, const std::string& source);

class TumDataset {
 public:
  /// Opens DIR and associates its lists. Throws InputError when the folder or a list is missing,
  /// a list is malformed, a listed image does not exist, or no RGB-D pair can be associated.
  explicit TumDataset(const std::string& directory, TumDatasetOptions options = {});

  const std::string& directory() const { return directory_; }
  /// Number of associated frames (times `loops`).
  int size() const { return static_cast<int>(entries_.size()) * options_.loops; }
  int framesPerLoop() const { return static_cast<int>(entries_.size()); }
  /// Timestamp of frame i (seconds). Later loops are shifted past the end of the sequence.
  double timestamp(int i) const;
  const RgbdEntry& entry(int i) const { return entries_[i % entries_.size()]; }

  /// Loads frame i. Throws InputError naming the file if an image is unreadable, has the wrong
  /// size, or the depth image is not single-channel 16-bit (or 32-bit float in metres).
  RgbdImages load(int i) const;

  /// True for composites written by `tkgslam augment` (a masks/ folder with per-frame truth).
  bool hasTruthMasks() const { return has_masks_; }

  /// Path of groundtruth.txt if the dataset has one.
  std::optional<std::string> groundTruthPath() const;
  /// The association file the pairs came from (empty: rgb.txt and depth.txt).
  const std::string& associationFile() const { return options_.associations; }

 private:
  /// The image size the camera config expects (any size when none is set).
  bool fitsCamera(const cv::Size& image) const;
  /// Fills entries_ from rgb.txt and depth.txt, associated by timestamps.
  void associateLists();
  /// Fills entries_ from the association file (TumDatasetOptions::associations).
  void readAssociationFile();

  std::string directory_;
  TumDatasetOptions options_;
  std::vector<RgbdEntry> entries_;
  double loop_period_ = 0.0;
  bool has_masks_ = false;
};

}  // namespace tkgslam::io
