#pragma once
// Opening a bag, with the error every tool gives: the path and what rosbag said; a camera's first usable
// camera_info in it.

#include <string>

#include <rosbag/bag.h>

#include "vocal/core/lens_distortion.h"
#include "vocal/core/pinhole_camera.h"

namespace vocal {

// Opens `path` in `mode` (rosbag::bagmode::Read or Write); throws InputError "PATH: cannot open bag
// (...)" or "PATH: cannot open bag for writing (...)".
void openBag(rosbag::Bag* bag, const std::string& path, rosbag::BagMode mode);

// The first camera_info on `topic` that converts; false when none does (each bad one is reported when
// the reader's main pass reaches it).
bool firstUsableCameraInfo(rosbag::Bag& bag, const std::string& topic, PinholeCamera* camera, LensDistortion* lens);

}  // namespace vocal
