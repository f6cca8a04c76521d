#include "tkgslam/tracking/TrajectoryRepair.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace tkgslam::tracking {

bool interpolateRecordsBefore(std::vector<FrameRecord>& records, size_t end, double last_tracked,
                              const std::vector<double>& lost) {
  // The records since the last tracked frame are the provisional ones before records[end]: every
  // frame posed in between (bridged or blurred) added one. Lost frames have none; they get theirs here.
  if (end >= records.size()) return false;
  size_t gap = 0;
  while (gap < end && records[end - 1 - gap].provisional) ++gap;
  if ((gap == 0 && lost.empty()) || gap == end) return false;  // nothing to fill, or no tracked record before it
  const FrameRecord& a = records[end - gap - 1];
  const FrameRecord& b = records[end];
  if (a.timestamp != last_tracked || !(b.timestamp > a.timestamp)) return false;
  const auto usable = [](const FrameRecord& r) { return r.reference && !r.reference->bad; };
  if (!usable(a) || !usable(b)) return false;
  const Pose T_a = a.T_cw(), T_b = b.T_cw();
  const double t_a = a.timestamp, t_b = b.timestamp;
  const auto reference = b.reference;
  // (Inserting invalidates a and b.)
  std::vector<FrameRecord> lost_records;
  for (double t : lost) lost_records.push_back({t, reference, Pose::Identity(), true});
  records.insert(records.begin() + std::ptrdiff_t(end), lost_records.begin(), lost_records.end());
  const size_t last = end + lost.size();
  for (size_t k = last - gap - lost.size(); k < last; ++k) {
    FrameRecord& r = records[k];
    if (!usable(r)) continue;
    const double s = (r.timestamp - t_a) / (t_b - t_a);
    r.T_cr = interpolatePose(T_a, T_b, s) * r.reference->T_wc();
    r.provisional = false;
    r.predicted = false;
    r.interpolated = true;
  }
  return true;
}

int interpolateAgain(std::vector<FrameRecord>& records) {
  int posed = 0;
  for (size_t i = 0; i < records.size();) {
    if (!records[i].interpolated) {
      ++i;
      continue;
    }
    size_t j = i;  // [i, j): a run of interpolated records
    while (j < records.size() && records[j].interpolated) ++j;
    if (i == 0 || j == records.size()) {
      i = j;
      continue;
    }
    const FrameRecord& a = records[i - 1];
    const FrameRecord& b = records[j];
    const auto usable = [](const FrameRecord& r) { return r.reference && !r.provisional; };
    if (usable(a) && usable(b) && b.timestamp > a.timestamp) {
      const Pose T_a = a.T_cw(), T_b = b.T_cw();
      for (size_t k = i; k < j; ++k) {
        FrameRecord& r = records[k];
        if (!r.reference) continue;
        r.setT_cw(interpolatePose(T_a, T_b, (r.timestamp - a.timestamp) / (b.timestamp - a.timestamp)));
        ++posed;
      }
    }
    i = j;
  }
  return posed;
}

int extrapolateEnd(std::vector<FrameRecord>& records, double fps, size_t steps) {
  // The run ended on bridged frames: no tracked frame after them to interpolate towards, and the
  // motion model moved them on by the velocity of the last tracked frame's own step.
  size_t last = records.size();  // the last record that is not provisional
  while (last > 0 && records[last - 1].provisional) --last;
  if (last == 0 || last == records.size()) return 0;
  --last;
  // Per-frame steps between the non-provisional records before it, as they are now.
  std::vector<Eigen::Matrix<double, 6, 1>> step_list;
  for (size_t k = last; k > 0 && step_list.size() < steps; --k) {
    const FrameRecord &a = records[k - 1], &b = records[k];
    if (a.provisional || !a.reference || !b.reference) break;
    const int n = std::max(1, int(std::lround((b.timestamp - a.timestamp) * fps)));
    const Pose S = poseRoot(b.T_cw() * a.T_cw().inverse(), n);
    const Eigen::AngleAxisd rotation(S.linear());
    Eigen::Matrix<double, 6, 1> v;
    v << rotation.angle() * rotation.axis(), S.translation();  // (rad, m)
    step_list.push_back(v);
  }
  if (step_list.empty()) return 0;
  // Each component's median: the last step alone may be far off (a frame tracked on few points
  // just before the view was covered: 7 cm per frame, 0.67 m after 10 frames, extreme_s32 TKGt).
  Eigen::Matrix<double, 6, 1> median;
  for (int c = 0; c < 6; ++c) {
    std::vector<double> x;
    for (const auto& v : step_list) x.push_back(v[c]);
    std::nth_element(x.begin(), x.begin() + std::ptrdiff_t(x.size() / 2), x.end());
    median[c] = x[x.size() / 2];
  }
  Pose step = Pose::Identity();
  step.linear() = expSO3(median.head<3>());
  step.translation() = median.tail<3>();
  const FrameRecord& L = records[last];
  const Pose T_L = L.T_cw();
  int posed = 0;
  for (size_t k = last + 1; k < records.size(); ++k) {
    FrameRecord& r = records[k];
    if (!r.reference || !r.predicted) continue;  // (one tracked on a blurred image keeps that pose)
    const int n = std::max(1, int(std::lround((r.timestamp - L.timestamp) * fps)));
    Pose T = T_L;
    for (int i = 0; i < n; ++i) T = step * T;
    r.setT_cw(orthonormalized(T));
    ++posed;
  }
  return posed;
}

int interpolateExcursions(std::vector<FrameRecord>& records, double min_off_m, double fps, size_t max_run) {
  const size_t n = records.size();
  std::vector<Pose> T(n);
  std::vector<Vec3> centre(n);  // camera centres (world, metres), kept with T
  std::vector<bool> usable(n);
  for (size_t k = 0; k < n; ++k) {
    usable[k] = records[k].reference != nullptr;
    if (!usable[k]) continue;
    T[k] = records[k].T_cw();
    centre[k] = T[k].inverse().translation();
  }
  // The run [i, i + w) between records i - 1 and i + w: how far its least-off record is from the
  // interpolation between them (0 = no excursion there). Not across a gap in the input.
  const auto offBy = [&](size_t i, size_t w) {
    if (i == 0 || i + w >= n) return 0.0;
    const size_t a = i - 1, b = i + w;
    const double t_a = records[a].timestamp, t_b = records[b].timestamp;
    if (!usable[a] || !usable[b] || !(t_b > t_a) || t_b - t_a > 1.5 * double(w + 1) / fps) return 0.0;
    double least = std::numeric_limits<double>::infinity();
    for (size_t k = i; k < b; ++k) {
      if (!usable[k]) return 0.0;
      const Vec3 on_line = centre[a] + (records[k].timestamp - t_a) / (t_b - t_a) * (centre[b] - centre[a]);
      least = std::min(least, (centre[k] - on_line).norm());
    }
    return least;
  };
  // off[w - 1][i]: offBy(i, w), recomputed near each replaced run.
  std::vector<std::vector<double>> off(max_run, std::vector<double>(n));
  const auto update = [&](size_t from, size_t to) {
    for (size_t w = 1; w <= max_run; ++w) {
      for (size_t i = from; i < std::min(to, n); ++i) off[w - 1][i] = offBy(i, w);
    }
  };
  update(0, n);
  int posed = 0;
  for (size_t round = 0; round < n; ++round) {  // (each round poses at least one record again)
    size_t best_i = 0, best_w = 0;
    double best = min_off_m;
    for (size_t w = 1; w <= max_run; ++w) {
      for (size_t i = 0; i < n; ++i) {
        if (!(off[w - 1][i] > best)) continue;
        best = off[w - 1][i];
        best_i = i;
        best_w = w;
      }
    }
    if (best_w == 0) break;
    const size_t a = best_i - 1, b = best_i + best_w;
    const double t_a = records[a].timestamp, t_b = records[b].timestamp;
    for (size_t k = best_i; k < b; ++k) {
      T[k] = interpolatePose(T[a], T[b], (records[k].timestamp - t_a) / (t_b - t_a));
      centre[k] = T[k].inverse().translation();
      records[k].setT_cw(T[k]);
      records[k].interpolated = true;
      ++posed;
    }
    update(best_i > max_run ? best_i - max_run : 0, b + 1);
  }
  return posed;
}

}  // namespace tkgslam::tracking
