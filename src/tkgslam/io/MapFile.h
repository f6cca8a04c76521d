#pragma once
// Saving a map and loading it into a later run. The file holds the active map segment: every
// keyframe (pose T_cw mapping world to camera, keypoints in raw and undistorted pixels, depth in
// metres, ORB descriptors, spanning-tree parent) and every map point (world position in metres,
// descriptor, viewing direction and distance range, observations). Binary, little-endian,
// versioned ("TKGSLAM-MAP", version kMapFileVersion); keypoint octaves and pixel positions only
// mean something with the camera and ORB pyramid the map was built with, so both are stored and a
// map is refused by a configuration with others.
#include <string>
#include <string_view>

#include "tkgslam/camera/PinholeCamera.h"
#include "tkgslam/data/Map.h"
#include "tkgslam/feature/ScalePyramid.h"

namespace tkgslam::io {

inline constexpr unsigned kMapFileVersion = 1;

/// The map's active keyframes and points as the bytes of a map file. Hold the map's lock.
std::string serializeMap(const data::Map& map, const camera::PinholeCamera& camera, const feature::ScalePyramid& pyramid);

/// Fills an empty map from the bytes of a map file: keyframes and points keep their ids (new
/// ones continue after them), links (observations, covisibility, spanning tree) are rebuilt.
/// The keyframes' frame ids become negative (-1 for the last), as frames of an earlier run; their
/// timestamps stay. Returns the number of keyframes. Throws InputError - naming what is wrong -
/// for bytes that are not a map file of this version, are truncated or inconsistent, or were made
/// with another camera or pyramid; the map is then left empty.
size_t deserializeMap(std::string_view bytes, data::Map& map, const camera::PinholeCamera& camera,
                      const feature::ScalePyramid& pyramid);

/// serializeMap to a file through writeOutputFile (an earlier map there is replaced only by a whole
/// new one). Throws InputError.
void writeMapFile(const std::string& path, const data::Map& map, const camera::PinholeCamera& camera,
                  const feature::ScalePyramid& pyramid);
/// deserializeMap from a file; the error message names the file. Throws InputError.
size_t readMapFile(const std::string& path, data::Map& map, const camera::PinholeCamera& camera,
                   const feature::ScalePyramid& pyramid);

}  // namespace tkgslam::io
