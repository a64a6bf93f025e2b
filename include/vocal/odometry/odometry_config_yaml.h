#pragma once

#include <string>

#include "vocal/odometry/odometry_config.h"

namespace vocal {

// Reads an odometry config YAML: keys are the OdometryConfig field names (mode, levels, iterations,
// icp_max_distance, ..., backend, opencl_platform, opencl_device); missing keys keep `defaults`.
// Throws InputError naming the file and key for unknown keys or malformed values.
OdometryConfig readOdometryConfigYaml(const std::string& path, const OdometryConfig& defaults = {});

}  // namespace vocal
