#pragma once
// Where the data shared by tests and benchmarks is: the repository (TKGSLAM_SOURCE_DIR, set by CMake)
// and ../shared next to it. No test framework here: the benchmarks include it too.
#include <filesystem>
#include <string>

namespace tkgslam::test {

inline std::filesystem::path sourceDir() { return TKGSLAM_SOURCE_DIR; }

/// ../shared relative to the repository root (empty path if missing).
inline std::filesystem::path sharedDir() {
  const auto p = sourceDir().parent_path() / "shared";
  return std::filesystem::is_directory(p) ? p : std::filesystem::path();
}

/// The bundled YOLOv5n export in ../shared.
inline std::string yoloModel() { return (sharedDir() / "models" / "yolov5n-coco-640.onnx").string(); }

inline std::filesystem::path fr1xyz() { return sharedDir() / "datasets" / "rgbd_dataset_freiburg1_xyz"; }

}  // namespace tkgslam::test
