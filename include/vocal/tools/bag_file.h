#pragma once
// Opening a bag, with the error every tool gives: the path and what rosbag said.

#include <string>

#include <rosbag/bag.h>

namespace vocal {

// Opens `path` in `mode` (rosbag::bagmode::Read or Write); throws InputError "PATH: cannot open bag
// (...)" or "PATH: cannot open bag for writing (...)".
void openBag(rosbag::Bag* bag, const std::string& path, rosbag::BagMode mode);

}  // namespace vocal
