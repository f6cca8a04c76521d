#pragma once
// The keyframes of a map by visual words, referred to by keyframe id: a KeyFrameIndex over a
// vocabulary trained on the keyframes' own descriptors (no vocabulary file to ship, and the words
// are those of the place being mapped). It can follow a growing map: keyframes made after the
// training are added with the vocabulary they were trained with, and the vocabulary is trained
// again once the map has grown by a given factor, so its words keep up with new places.
#include <memory>
#include <vector>

#include "tkgslam/data/FrameFeatures.h"
#include "tkgslam/data/KeyFrame.h"
#include "tkgslam/place/KeyFrameIndex.h"

namespace tkgslam::place {

struct DatabaseEntry {
  long id = -1;                                          ///< the keyframe's id
  std::shared_ptr<const data::FrameFeatures> features;  ///< its descriptors and exclusion flags
};

/// The entries of the keyframes that can be indexed (not culled, with features), in their order.
/// Read them under the map lock.
std::vector<DatabaseEntry> entriesOf(const std::vector<std::shared_ptr<data::KeyFrame>>& keyframes);

class KeyFrameDatabase {
 public:
  /// `retrain_growth`: train again when given at least this many times the keyframes the
  /// vocabulary was trained on (0 = train once).
  explicit KeyFrameDatabase(double retrain_growth = 0) : retrain_growth_(retrain_growth) {}

  /// Makes `keyframes` searchable (the map's keyframes in id order; ones already indexed are
  /// skipped). Trains the vocabulary on all their descriptors the first time and when the map has
  /// grown by `retrain_growth`; returns true if it trained. Keyframes without descriptors are
  /// indexed with an empty bag. Nothing is indexed while none of them has a descriptor.
  bool update(const std::vector<DatabaseEntry>& keyframes);

  bool trained() const { return index_ != nullptr; }
  size_t size() const { return ids_.size(); }
  int words() const { return index_ ? index_->vocabulary().words() : 0; }
  /// The highest id indexed (-1 if none).
  long newestId() const { return ids_.empty() ? -1 : ids_.back(); }

  /// Ids of the indexed keyframes that share words with `query`, most similar first, at most
  /// `n`; with `among`, only keyframes whose id it holds (sorted ascending) are considered.
  std::vector<long> mostSimilar(const data::FrameFeatures& query, size_t n,
                                const std::vector<long>* among = nullptr) const;

 private:
  /// False (and nothing changed) if none of them has a descriptor.
  bool train(const std::vector<DatabaseEntry>& keyframes);

  double retrain_growth_;
  size_t trained_on_ = 0;
  std::unique_ptr<KeyFrameIndex> index_;
  std::vector<long> ids_;  ///< per index position, ascending
};

}  // namespace tkgslam::place
