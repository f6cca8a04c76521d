#pragma once
// glibc malloc settings for a process that allocates a few MB of images every frame. The library
// never calls this itself (process-wide settings belong to the program); the tkgslam CLI, the
// benchmarks and the example application call it first thing in main().

namespace tkgslam::common {

/// Fixes glibc's mmap threshold at 4 MB and its trim threshold at 64 MB (no-op elsewhere).
///
/// With glibc's adaptive thresholds the mmap threshold follows the largest block freed so far, so
/// a frame's images (1.2 MB float depth, pyramid levels, 300 kB gradient images) went back and
/// forth to the kernel, or the heap was trimmed under them, and every page was faulted in again
/// each frame: on fr1_xyz 425 000 page faults, ORB extraction 12 instead of 7-8 ms a frame, reading
/// a frame 14.6 instead of 4.4 ms, the blur measure 8.1 instead of 0.19 ms. Blocks under 4 MB now
/// come from the heap, which keeps up to 64 MB free; the detector's larger blobs stay mapped (a
/// 32 MB threshold put them on the heap too: 28 MB more resident memory).
void tuneMallocForFrames();

}  // namespace tkgslam::common
