#pragma once
// Repairs of the recorded trajectory (the tracker's FrameRecords, in timestamp order): poses for
// frames that were bridged, lost or tracked badly, from the well-tracked frames around them.
// Pure functions of the records and the keyframes they reference; the caller holds the map lock.
#include <cstddef>
#include <vector>

#include "tkgslam/tracking/FrameRecord.h"

namespace tkgslam::tracking {

/// Tracking resumed at records[end] after frames posed without being tracked: the provisional
/// records just before it get the pose interpolated (by timestamp) between the last tracked record
/// before them, which must be the frame at `last_tracked` (timestamp, s), and records[end]. The
/// `lost` frames (timestamps, after the provisional ones) had no record: they get one, inserted
/// before records[end], interpolated too. All of them are marked `interpolated`. False if there is
/// nothing to interpolate from (the records are left as they are).
bool interpolateRecordsBefore(std::vector<FrameRecord>& records, size_t end, double last_tracked,
                              const std::vector<double>& lost);

/// Interpolates each run of `interpolated` records again, between the current poses of the
/// records either side (a loop closure or a pose check may have moved those since, while an
/// interpolated record follows only its own reference keyframe). Returns the records posed again.
int interpolateAgain(std::vector<FrameRecord>& records);

/// Poses the predicted records after the last non-provisional one again (bridged at the end of a
/// run, so nothing later interpolates them): that record's pose moved on by the component-wise
/// median per-frame step of the `steps` steps before it, not by the velocity of its own last step.
/// Records tracked on blurred images there keep their poses. `fps`: frames per second, to count
/// frame periods between timestamps. Returns the records posed again.
int extrapolateEnd(std::vector<FrameRecord>& records, double fps, size_t steps);

/// Interpolates excursions: runs of at most `max_run` records whose camera centres are all further
/// than `min_off_m` metres from the interpolation between the records either side, the furthest
/// run first (a record next to an excursion is itself off the line through its neighbours). Not
/// across a gap in the input (records further apart than 1.5 frame periods each, at `fps`).
/// Returns the records posed again.
int interpolateExcursions(std::vector<FrameRecord>& records, double min_off_m, double fps, size_t max_run);

}  // namespace tkgslam::tracking
