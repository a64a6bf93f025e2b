#pragma once

#include <string>

#include "vocal/odometry/odometry_config.h"

namespace YAML {
class Node;
}

namespace vocal {

// Reads an odometry config YAML: keys are the OdometryConfig field names (mode, levels, iterations,
// icp_max_distance, ..., backend, opencl_platform, opencl_device); missing keys keep `defaults`.
// Throws InputError naming the file and key for unknown keys or malformed values.
OdometryConfig readOdometryConfigYaml(const std::string& path, const OdometryConfig& defaults = {});

// The same from a YAML map already in memory (a nodelet's private parameters): keys other than the
// OdometryConfig fields are an error unless `ignore_other_keys`. `what` names the source in errors.
OdometryConfig odometryConfigFromYaml(const YAML::Node& settings, const std::string& what, const OdometryConfig& defaults,
                                      bool ignore_other_keys);

}  // namespace vocal
