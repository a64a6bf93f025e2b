#pragma once
// Camera intrinsics in the ROS camera_info YAML layout (camera_calibration_parsers), so a file
// written here also serves as a driver's camera_info_url. An extra `depth_scale` key records raw
// depth units per metre.

#include <string>

#include "vocal/core/pinhole_camera.h"

namespace vocal {

// Throws InputError naming the file and the key that is missing or malformed.
PinholeCamera readCameraYaml(const std::string& path);
void writeCameraYaml(const std::string& path, const PinholeCamera& camera, const std::string& camera_name);

}  // namespace vocal
