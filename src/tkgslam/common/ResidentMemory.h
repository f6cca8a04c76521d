#pragma once
// Resident memory of this process, for the memory log of long runs (`tkgslam run` writes
// memory.tsv every 100 frames).

namespace tkgslam {

/// Resident set size in MiB (from /proc/self/statm); 0 where /proc is not available.
double residentMemoryMiB();

}  // namespace tkgslam
