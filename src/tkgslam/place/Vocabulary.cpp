#include "tkgslam/place/Vocabulary.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <numeric>
#include <random>

#include "tkgslam/common/Error.h"
#include "tkgslam/data/MapPoint.h"

namespace tkgslam::place {
namespace {

using data::descriptorDistance;

// Per bit, the value most members have (ties: 0) - the "centre" of binary descriptors.
std::array<uint8_t, 32> majority(const std::vector<const uint8_t*>& members) {
  std::array<int, 256> ones{};
  for (const uint8_t* d : members) {
    for (int b = 0; b < 256; ++b) ones[b] += (d[b >> 3] >> (b & 7)) & 1;
  }
  std::array<uint8_t, 32> c{};
  for (int b = 0; b < 256; ++b) {
    if (2 * ones[b] > int(members.size())) c[b >> 3] |= uint8_t(1u << (b & 7));
  }
  return c;
}

// Greedy k-means++ seeding: each next centre is the best (least summed squared distance of the
// members to their nearest centre) of a few drawn with probability proportional to that squared
// distance; plain k-means++ puts two seeds in one cluster now and then, and k-majority does not
// recover. The generator is fixed, so the draw is reproducible.
std::vector<std::array<uint8_t, 32>> seedCentres(const std::vector<const uint8_t*>& members, int k, std::mt19937& rng) {
  std::vector<std::array<uint8_t, 32>> centres;
  auto take = [&](const uint8_t* d) {
    std::array<uint8_t, 32> c;
    std::memcpy(c.data(), d, 32);
    centres.push_back(c);
  };
  const int tries = 2 + int(std::log(double(k)));
  take(members[rng() % members.size()]);
  std::vector<double> d2(members.size());
  for (size_t i = 0; i < members.size(); ++i) {
    const double d = descriptorDistance(members[i], centres[0].data());
    d2[i] = d * d;
  }
  std::vector<double> with(members.size()), best_with;
  while (int(centres.size()) < k) {
    const double total = std::accumulate(d2.begin(), d2.end(), 0.0);
    if (total <= 0) break;  // every member equals a centre: fewer distinct clusters than k
    size_t best = 0;
    double best_total = std::numeric_limits<double>::max();
    for (int t = 0; t < tries; ++t) {
      double r = double(rng()) / (double(std::mt19937::max()) + 1.0) * total;
      size_t pick = 0;
      for (; pick + 1 < members.size(); ++pick) {
        r -= d2[pick];
        if (r < 0) break;
      }
      double sum = 0;
      for (size_t i = 0; i < members.size(); ++i) {
        const double d = descriptorDistance(members[i], members[pick]);
        with[i] = std::min(d2[i], d * d);
        sum += with[i];
      }
      if (sum < best_total) best_total = sum, best = pick, best_with = with;
    }
    take(members[best]);
    d2 = best_with;
  }
  return centres;
}

int nearest(const uint8_t* d, const std::array<uint8_t, 32>* centres, int n) {
  int best = 0, best_dist = std::numeric_limits<int>::max();
  for (int i = 0; i < n; ++i) {
    const int dist = descriptorDistance(d, centres[i].data());
    if (dist < best_dist) best_dist = dist, best = i;
  }
  return best;
}

}  // namespace

Vocabulary Vocabulary::train(const cv::Mat& descriptors, const VocabularyOptions& o) {
  if (o.branching < 2 || o.depth < 1 || o.iterations < 1 || o.max_training < 1)
    throw InputError("vocabulary: branching >= 2, depth >= 1, iterations >= 1 and max_training >= 1 are needed");
  Vocabulary v;
  if (descriptors.empty()) return v;
  if (descriptors.type() != CV_8U || descriptors.cols != 32 || !descriptors.isContinuous())
    throw InputError("vocabulary: descriptors must be continuous N x 32 CV_8U rows");
  std::vector<const uint8_t*> members;
  const int n = descriptors.rows;
  const int step = std::max(1, (n + o.max_training - 1) / o.max_training);
  for (int i = 0; i < n; i += step) members.push_back(descriptors.ptr<uint8_t>(i));
  v.nodes_.emplace_back();  // the root: its centre is never compared with
  unsigned seed = o.seed;
  v.split(0, members, 0, o, seed);
  return v;
}

void Vocabulary::split(int node, std::vector<const uint8_t*>& members, int level, const VocabularyOptions& o,
                       unsigned& seed) {
  if (level == o.depth || members.size() <= 1) {
    nodes_[node].word = words_++;
    return;
  }
  std::mt19937 rng(seed++);
  const int k = int(std::min<size_t>(size_t(o.branching), members.size()));
  auto centres = seedCentres(members, k, rng);
  const int m = int(centres.size());
  // k-majority: assign, then move each centre to its members' majority, until nothing moves.
  std::vector<int> owner(members.size(), -1);
  std::vector<std::vector<const uint8_t*>> parts(m);
  bool settled = false;
  for (int it = 0; it < o.iterations; ++it) {
    settled = true;
    for (auto& p : parts) p.clear();
    for (size_t i = 0; i < members.size(); ++i) {
      const int c = nearest(members[i], centres.data(), m);
      settled &= c == owner[i];
      owner[i] = c;
      parts[c].push_back(members[i]);
    }
    if (settled) break;
    for (int c = 0; c < m; ++c) {
      if (!parts[c].empty()) centres[c] = majority(parts[c]);
    }
  }
  if (!settled) {  // the last update moved the centres: the members go to the nearest of those
    for (auto& p : parts) p.clear();
    for (const uint8_t* d : members) parts[nearest(d, centres.data(), m)].push_back(d);
  }
  const int first = int(nodes_.size());
  nodes_[node].first_child = first;
  nodes_[node].children = m;
  for (int c = 0; c < m; ++c) {
    nodes_.emplace_back();
    nodes_[first + c].centre = centres[c];
  }
  std::vector<const uint8_t*>().swap(members);  // the parts hold them now
  for (int c = 0; c < m; ++c) split(first + c, parts[c], level + 1, o, seed);
}

int Vocabulary::wordOf(const uint8_t* descriptor) const {
  if (nodes_.empty()) return -1;
  int node = 0;
  while (nodes_[node].children > 0) {
    const Node& n = nodes_[node];
    int best = n.first_child, best_dist = std::numeric_limits<int>::max();
    for (int c = n.first_child; c < n.first_child + n.children; ++c) {
      const int dist = descriptorDistance(descriptor, nodes_[c].centre.data());
      if (dist < best_dist) best_dist = dist, best = c;
    }
    node = best;
  }
  return nodes_[node].word;
}

}  // namespace tkgslam::place
