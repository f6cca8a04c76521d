#pragma once
// Which keyframes look like a frame: bags of visual words weighted by tf-idf and an inverted
// file over them, the way ORB-SLAM2 finds relocalisation candidates with DBoW2 - so a lost
// frame is tried against the few keyframes that share its words instead of every keyframe of a
// loaded map. Built over a set of keyframes (referred to by their position in it); more can be
// added later, weighed with the idf of the first set (as DBoW2 keeps its vocabulary's).
#include <cstdint>
#include <map>
#include <utility>
#include <vector>

#include <opencv2/core.hpp>

#include "tkgslam/place/Vocabulary.h"

namespace tkgslam::place {

/// A bag of words: (word, weight) sorted by word, weights summing to 1.
using BagOfWords = std::vector<std::pair<int, float>>;

struct PlaceCandidate {
  int index = -1;     ///< position in the indexed set
  double score = 0;   ///< in (0, 1]: 1 = the same bag of words
};

class KeyFrameIndex {
 public:
  /// `descriptors[i]`: keyframe i's ORB descriptors (N x 32 CV_8U rows); `excluded[i]`, if not
  /// empty, marks rows to leave out (e.g. keypoints on people), one flag per row. Throws
  /// InputError on other shapes.
  KeyFrameIndex(Vocabulary vocabulary, const std::vector<cv::Mat>& descriptors,
                const std::vector<std::vector<char>>& excluded = {});

  /// Indexes one more keyframe (shapes as above); returns its position. Words are weighed with the
  /// idf of the keyframes the index was built with.
  int add(const cv::Mat& descriptors, const std::vector<char>& excluded = {});

  size_t size() const { return bags_.size(); }
  const Vocabulary& vocabulary() const { return vocabulary_; }

  /// The indexed keyframes sharing words with these descriptors, most similar first (L1 score
  /// of the normalised bags, as DBoW2; ties by position), at most `n`. `excluded` as above.
  std::vector<PlaceCandidate> query(const cv::Mat& descriptors, size_t n, const std::vector<char>& excluded = {}) const;

 private:
  /// Word counts weighted by idf and normalised to sum 1 (words of idf 0 left out).
  BagOfWords weigh(const std::map<int, int>& counts) const;
  int insert(BagOfWords bag);

  Vocabulary vocabulary_;
  std::vector<float> idf_;                                   ///< per word: log(keyframes / keyframes with it)
  std::vector<BagOfWords> bags_;                             ///< per keyframe
  std::vector<std::vector<std::pair<int, float>>> inverted_;  ///< per word: (keyframe, weight)
};

}  // namespace tkgslam::place
