#include "tkgslam/place/KeyFrameIndex.h"

#include <algorithm>
#include <cmath>
#include <map>

#include "tkgslam/common/Error.h"

namespace tkgslam::place {
namespace {

// Word counts of the rows not excluded.
std::map<int, int> countWords(const Vocabulary& voc, const cv::Mat& descriptors, const std::vector<char>& excluded) {
  if (!descriptors.empty() && (descriptors.type() != CV_8U || descriptors.cols != 32))
    throw InputError("keyframe index: descriptors must be N x 32 CV_8U rows");
  if (!excluded.empty() && excluded.size() != size_t(descriptors.rows))
    throw InputError("keyframe index: one exclusion flag per descriptor row is needed");
  std::map<int, int> counts;
  for (int i = 0; i < descriptors.rows; ++i) {
    if (!excluded.empty() && excluded[size_t(i)]) continue;
    const int w = voc.wordOf(descriptors.ptr<uint8_t>(i));
    if (w >= 0) ++counts[w];
  }
  return counts;
}

}  // namespace

KeyFrameIndex::KeyFrameIndex(Vocabulary vocabulary, const std::vector<cv::Mat>& descriptors,
                             const std::vector<std::vector<char>>& excluded)
    : vocabulary_(std::move(vocabulary)), idf_(size_t(vocabulary_.words()), 0.f), inverted_(idf_.size()) {
  static const std::vector<char> none;
  std::vector<std::map<int, int>> counts;
  std::vector<int> keyframes_with(idf_.size(), 0);
  for (size_t k = 0; k < descriptors.size(); ++k) {
    counts.push_back(countWords(vocabulary_, descriptors[k], k < excluded.size() ? excluded[k] : none));
    for (const auto& wc : counts.back()) ++keyframes_with[size_t(wc.first)];
  }
  // A word every keyframe has tells them apart no better than none (idf 0).
  const double n = double(descriptors.size());
  for (size_t w = 0; w < idf_.size(); ++w) {
    if (keyframes_with[w] > 0) idf_[w] = float(std::log(n / keyframes_with[w]));
  }
  for (const auto& c : counts) insert(weigh(c));
}

int KeyFrameIndex::add(const cv::Mat& descriptors, const std::vector<char>& excluded) {
  return insert(weigh(countWords(vocabulary_, descriptors, excluded)));
}

int KeyFrameIndex::insert(BagOfWords bag) {
  const int k = int(bags_.size());
  for (const auto& [w, weight] : bag) inverted_[size_t(w)].emplace_back(k, weight);
  bags_.push_back(std::move(bag));
  return k;
}

BagOfWords KeyFrameIndex::weigh(const std::map<int, int>& counts) const {
  BagOfWords bag;
  double total = 0;
  for (const auto& [w, c] : counts) {
    const float weight = float(c) * idf_[size_t(w)];
    if (weight <= 0) continue;
    bag.emplace_back(w, weight);
    total += weight;
  }
  for (auto& wv : bag) wv.second = float(wv.second / total);
  return bag;
}

std::vector<PlaceCandidate> KeyFrameIndex::query(const cv::Mat& descriptors, size_t n,
                                                 const std::vector<char>& excluded) const {
  // For bags that each sum to 1, DBoW2's L1 score 1 - |a - b|_1 / 2 is half the sum, over the
  // words both have, of |a| + |b| - |a - b|: only the inverted file's entries are visited.
  std::vector<double> score(bags_.size(), 0.0);
  for (const auto& [w, a] : weigh(countWords(vocabulary_, descriptors, excluded))) {
    for (const auto& [k, b] : inverted_[size_t(w)]) score[size_t(k)] += a + b - std::abs(a - b);
  }
  std::vector<PlaceCandidate> out;
  for (size_t k = 0; k < score.size(); ++k) {
    if (score[k] > 0) out.push_back({int(k), 0.5 * score[k]});
  }
  std::stable_sort(out.begin(), out.end(), [](const auto& x, const auto& y) { return x.score > y.score; });
  if (out.size() > n) out.resize(n);
  return out;
}

}  // namespace tkgslam::place
