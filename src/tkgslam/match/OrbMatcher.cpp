#include "tkgslam/match/OrbMatcher.h"

#include <algorithm>
#include <cmath>

#include "tkgslam/match/NearestDescriptors.h"

namespace tkgslam::match {

using data::descriptorDistance;

void OrbMatcher::rotationConsistency(const std::vector<float>& diffs, std::vector<char>& keep) {
  constexpr int kBins = 30;
  std::vector<std::vector<int>> hist(kBins);
  for (size_t i = 0; i < diffs.size(); ++i) {
    if (!keep[i]) continue;
    float rot = diffs[i];
    if (rot < 0) rot += 360.0f;
    int bin = int(std::lround(rot * kBins / 360.0f)) % kBins;
    hist[bin].push_back(int(i));
  }
  int m1 = -1, m2 = -1, m3 = -1;
  auto size = [&](int b) { return b < 0 ? 0 : int(hist[b].size()); };
  for (int b = 0; b < kBins; ++b) {
    const int s = int(hist[b].size());
    if (s > size(m1)) {
      m3 = m2;
      m2 = m1;
      m1 = b;
    } else if (s > size(m2)) {
      m3 = m2;
      m2 = b;
    } else if (s > size(m3)) {
      m3 = b;
    }
  }
  // Secondary bins count only if they are not much smaller than the main one.
  if (size(m2) < 0.1 * size(m1)) m2 = m3 = -1;
  else if (size(m3) < 0.1 * size(m1)) m3 = -1;
  for (int b = 0; b < kBins; ++b) {
    if (b == m1 || b == m2 || b == m3) continue;
    for (int i : hist[b]) keep[i] = 0;
  }
}

int OrbMatcher::searchByProjection(data::Frame& cur, const data::Frame& last, float th) const {
  const Mat3 R = cur.T_cw.linear();
  const Vec3 t = cur.T_cw.translation();
  // Camera motion along its axis decides which pyramid levels can hold the point.
  const Vec3 t_lc = last.T_cw * cur.centre();
  const double baseline = bf_ / cam_.fx();
  const bool forward = t_lc.z() > baseline, backward = -t_lc.z() > baseline;
  const auto& F = *cur.features;
  std::vector<int> idx_cur;
  std::vector<float> diffs;
  std::vector<char> keep;
  for (int i = 0; i < last.size(); ++i) {
    const auto& mp = last.map_points[i];
    if (!mp || last.outlier[i] || mp->bad) continue;
    const Vec3 pc = R * mp->pos_w + t;
    if (pc.z() <= 0) continue;
    const Vec2 uv = cam_.project(pc);
    if (!cam_.inImage(uv)) continue;
    const int octave = last.features->ideal[i].octave;
    const float radius = th * float(pyr_.scales[octave]);
    std::vector<int> cand;
    if (forward) cand = F.featuresInArea(float(uv.x()), float(uv.y()), radius, octave);
    else if (backward) cand = F.featuresInArea(float(uv.x()), float(uv.y()), radius, 0, octave);
    else cand = F.featuresInArea(float(uv.x()), float(uv.y()), radius, std::max(octave - 1, 0), octave + 1);
    const double ur = uv.x() - bf_ / pc.z();
    int best = 256, best_idx = -1;
    for (int j : cand) {
      if (F.excluded[j]) continue;
      if (cur.map_points[j] && !cur.map_points[j]->observations.empty()) continue;
      if (F.u_right[j] > 0 && std::abs(ur - F.u_right[j]) > radius) continue;
      const int d = descriptorDistance(mp->descriptor.ptr<uint8_t>(), F.descriptors.ptr<uint8_t>(j));
      if (d < best) {
        best = d;
        best_idx = j;
      }
    }
    if (best <= kThHigh && best_idx >= 0) {
      cur.map_points[best_idx] = mp;
      idx_cur.push_back(best_idx);
      diffs.push_back(last.features->ideal[i].angle - F.ideal[best_idx].angle);
      keep.push_back(1);
    }
  }
  rotationConsistency(diffs, keep);
  int n = 0;
  for (size_t k = 0; k < idx_cur.size(); ++k) {
    if (keep[k]) ++n;
    else cur.map_points[idx_cur[k]].reset();
  }
  return n;
}

bool OrbMatcher::isInFrustum(data::MapPoint& mp, const Pose& T_cw, double min_view_cos) const {
  mp.track_in_view = false;
  const Vec3 pc = T_cw * mp.pos_w;
  if (pc.z() <= 0) return false;
  const Vec2 uv = cam_.project(pc);
  if (!cam_.inImage(uv)) return false;
  const Vec3 PO = mp.pos_w - T_cw.inverse().translation();
  const double dist = PO.norm();
  if (dist < 0.8 * mp.min_distance || dist > 1.2 * mp.max_distance) return false;
  const double view_cos = PO.dot(mp.normal) / dist;
  if (view_cos < min_view_cos) return false;
  mp.track_in_view = true;
  mp.track_x = float(uv.x());
  mp.track_y = float(uv.y());
  mp.track_x_right = float(uv.x() - bf_ / pc.z());
  mp.track_level = mp.predictScale(dist, pyr_);
  mp.track_view_cos = float(view_cos);
  return true;
}

int OrbMatcher::searchByProjection(data::Frame& cur, const std::vector<std::shared_ptr<data::MapPoint>>& points,
                                   float th) const {
  const auto& F = *cur.features;
  int n = 0;
  for (const auto& mp : points) {
    if (!mp->track_in_view || mp->bad) continue;
    const int level = mp->track_level;
    const float r = th * (mp->track_view_cos > 0.998f ? 2.5f : 4.0f) * float(pyr_.scales[level]);
    const auto cand = F.featuresInArea(mp->track_x, mp->track_y, r, level - 1, level);
    int best = 256, best2 = 256, best_level = -1, best_level2 = -1, best_idx = -1;
    for (int j : cand) {
      if (F.excluded[j]) continue;
      if (cur.map_points[j] && !cur.map_points[j]->observations.empty()) continue;
      if (F.u_right[j] > 0 && std::abs(mp->track_x_right - F.u_right[j]) > r) continue;
      const int d = descriptorDistance(mp->descriptor.ptr<uint8_t>(), F.descriptors.ptr<uint8_t>(j));
      if (d < best) {
        best2 = best;
        best_level2 = best_level;
        best = d;
        best_level = F.ideal[j].octave;
        best_idx = j;
      } else if (d < best2) {
        best2 = d;
        best_level2 = F.ideal[j].octave;
      }
    }
    if (best > kThHigh) continue;
    if (best_level == best_level2 && best > 0.8 * best2) continue;
    cur.map_points[best_idx] = mp;
    ++n;
  }
  return n;
}

int OrbMatcher::searchByDescriptors(const data::KeyFrame& kf, const data::Frame& cur,
                                    std::vector<std::shared_ptr<data::MapPoint>>& matches) const {
  matches.assign(cur.size(), nullptr);
  const auto& F = *cur.features;
  std::vector<int> best_for(cur.size(), 257);
  std::vector<int> kf_idx, cur_idx;
  std::vector<float> diffs;
  for (size_t i = 0; i < kf.map_points.size(); ++i) {
    const auto& mp = kf.map_points[i];
    if (!mp || mp->bad) continue;
    const auto [best, best2, best_j] = nearestTwoDescriptors(kf.features->descriptors.ptr<uint8_t>(int(i)),
                                                             F.descriptors.data, F.descriptors.step, cur.size(),
                                                             F.excluded.data());
    if (best_j < 0 || best > kThLow || best >= 0.7 * best2) continue;
    if (best >= best_for[best_j]) continue;  // keep the better of two claims on one keypoint
    best_for[best_j] = best;
    kf_idx.push_back(int(i));
    cur_idx.push_back(best_j);
    diffs.push_back(kf.features->ideal[i].angle - F.ideal[best_j].angle);
  }
  std::vector<char> keep(kf_idx.size(), 1);
  for (size_t k = 0; k < kf_idx.size(); ++k) {
    if (best_for[cur_idx[k]] != descriptorDistance(kf.features->descriptors.row(kf_idx[k]),
                                                   F.descriptors.row(cur_idx[k]))) {
      keep[k] = 0;  // superseded by a better claim
    }
  }
  rotationConsistency(diffs, keep);
  int n = 0;
  for (size_t k = 0; k < kf_idx.size(); ++k) {
    if (!keep[k] || matches[cur_idx[k]]) continue;
    matches[cur_idx[k]] = kf.map_points[kf_idx[k]];
    ++n;
  }
  return n;
}

int OrbMatcher::fuse(data::Map& map, data::KeyFrame& kf, const std::vector<std::shared_ptr<data::MapPoint>>& points,
                     float th) const {
  const auto& F = *kf.features;
  const Mat3 R = kf.T_cw().linear();
  const Vec3 t = kf.T_cw().translation();
  const Vec3 O = kf.centre();
  int fused = 0;
  for (const auto& mp : points) {
    if (!mp || mp->bad || mp->observations.count(&kf)) continue;
    const Vec3 pc = R * mp->pos_w + t;
    if (pc.z() <= 0) continue;
    const Vec2 uv = cam_.project(pc);
    if (!cam_.inImage(uv)) continue;
    const Vec3 po = mp->pos_w - O;
    const double dist = po.norm();
    if (dist < 0.8 * mp->min_distance || dist > 1.2 * mp->max_distance) continue;
    if (po.dot(mp->normal) < 0.5 * dist) continue;  // viewing angle > 60 degrees
    const int level = mp->predictScale(dist, pyr_);
    const float radius = th * float(pyr_.scales[level]);
    const double ur = uv.x() - bf_ / pc.z();
    int best = 256, best_idx = -1;
    for (int j : F.featuresInArea(float(uv.x()), float(uv.y()), radius)) {
      if (F.excluded[j]) continue;
      const auto& kp = F.ideal[j];
      if (kp.octave < level - 1 || kp.octave > level) continue;
      const double ex = uv.x() - kp.pt.x, ey = uv.y() - kp.pt.y;
      const double inv_s2 = pyr_.inv_sigma2[kp.octave];
      if (F.u_right[j] > 0) {
        const double er = ur - F.u_right[j];
        if ((ex * ex + ey * ey + er * er) * inv_s2 > 7.8) continue;
      } else if ((ex * ex + ey * ey) * inv_s2 > 5.99) {
        continue;
      }
      const int d = descriptorDistance(mp->descriptor.ptr<uint8_t>(), F.descriptors.ptr<uint8_t>(j));
      if (d < best) {
        best = d;
        best_idx = j;
      }
    }
    if (best_idx < 0 || best > kThLow) continue;
    if (auto existing = kf.map_points[best_idx]; existing && !existing->bad) {
      if (existing->observationWeight() > mp->observationWeight()) map.replaceMapPoint(mp.get(), existing);
      else map.replaceMapPoint(existing.get(), mp);
    } else {
      mp->observations[&kf] = best_idx;
      kf.map_points[best_idx] = mp;
    }
    ++fused;
  }
  return fused;
}

}  // namespace tkgslam::match
