#pragma once
// A vocabulary tree of ORB descriptors (hierarchical k-majority clustering, as DBoW2 builds
// one), trained on the descriptors it is given - a loaded map's own keyframes - so no
// vocabulary file has to be shipped or downloaded. Training is deterministic (seeded).
#include <array>
#include <cstdint>
#include <vector>

#include <opencv2/core.hpp>

namespace tkgslam::place {

struct VocabularyOptions {
  int branching = 10;             ///< children per node
  int depth = 5;                  ///< levels below the root: up to branching^depth words
  int iterations = 6;             ///< k-majority refinements per node
  int max_training = 100000;      ///< descriptors used for training (an even subsample of more)
  unsigned seed = 1;              ///< k-means++ seeding
};

class Vocabulary {
 public:
  /// An empty vocabulary (no words; wordOf returns -1).
  Vocabulary() = default;
  /// Trains on `descriptors` (N x 32, CV_8U, one ORB descriptor per row).
  static Vocabulary train(const cv::Mat& descriptors, const VocabularyOptions& options = {});

  int words() const { return words_; }
  /// The leaf (word id in [0, words())) a 32-byte descriptor falls into; -1 if empty.
  int wordOf(const uint8_t* descriptor) const;

 private:
  struct Node {
    std::array<uint8_t, 32> centre{};
    int first_child = -1;  ///< children are nodes [first_child, first_child + children)
    int children = 0;
    int word = -1;         ///< leaves only
  };
  void split(int node, std::vector<const uint8_t*>& members, int level, const VocabularyOptions& o,
             unsigned& seed);

  std::vector<Node> nodes_;
  int words_ = 0;
};

}  // namespace tkgslam::place
