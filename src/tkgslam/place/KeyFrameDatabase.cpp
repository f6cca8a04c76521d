#include "tkgslam/place/KeyFrameDatabase.h"

#include <algorithm>

namespace tkgslam::place {
namespace {

const cv::Mat& descriptorsOf(const DatabaseEntry& e) {
  static const cv::Mat none;
  return e.features ? e.features->descriptors : none;
}

const std::vector<char>& excludedOf(const DatabaseEntry& e) {
  static const std::vector<char> none;
  return e.features ? e.features->excluded : none;
}

}  // namespace

std::vector<DatabaseEntry> entriesOf(const std::vector<std::shared_ptr<data::KeyFrame>>& keyframes) {
  std::vector<DatabaseEntry> out;
  for (const auto& kf : keyframes) {
    if (!kf->bad && kf->features) out.push_back({kf->id, kf->features});
  }
  return out;
}

bool KeyFrameDatabase::update(const std::vector<DatabaseEntry>& keyframes) {
  const bool grown = retrain_growth_ > 0 && double(keyframes.size()) >= retrain_growth_ * double(trained_on_);
  if ((!index_ || grown) && train(keyframes)) return true;
  if (!index_) return false;
  for (const auto& e : keyframes) {
    if (e.id <= newestId()) continue;
    index_->add(descriptorsOf(e), excludedOf(e));
    ids_.push_back(e.id);
  }
  return false;
}

bool KeyFrameDatabase::train(const std::vector<DatabaseEntry>& keyframes) {
  std::vector<cv::Mat> descriptors, training;  // vconcat refuses empty blocks
  std::vector<std::vector<char>> excluded;
  for (const auto& e : keyframes) {
    descriptors.push_back(descriptorsOf(e));
    excluded.push_back(excludedOf(e));
    if (!descriptors.back().empty()) training.push_back(descriptors.back());
  }
  if (training.empty()) return false;  // nothing to learn words from
  cv::Mat all;
  cv::vconcat(training, all);
  index_ = std::make_unique<KeyFrameIndex>(Vocabulary::train(all), descriptors, excluded);
  ids_.clear();
  for (const auto& e : keyframes) ids_.push_back(e.id);
  trained_on_ = keyframes.size();
  return true;
}

std::vector<long> KeyFrameDatabase::mostSimilar(const data::FrameFeatures& query, size_t n,
                                                const std::vector<long>* among) const {
  std::vector<long> out;
  if (!index_) return out;
  // Every indexed keyframe is ranked when only some may be answered.
  for (const auto& c : index_->query(query.descriptors, among ? ids_.size() : n, query.excluded)) {
    if (out.size() >= n) break;
    const long id = ids_[size_t(c.index)];
    if (!among || std::binary_search(among->begin(), among->end(), id)) out.push_back(id);
  }
  return out;
}

}  // namespace tkgslam::place
