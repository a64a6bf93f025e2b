#pragma once
// ROS parameters (XmlRpc values, as rosparam loads them from YAML) back into YAML, so a nodelet's
// private parameters go through the same parser, checks and error messages as a config file.

#include <XmlRpcValue.h>
#include <yaml-cpp/yaml.h>

namespace vocal {

YAML::Node toYaml(XmlRpc::XmlRpcValue& value);

}  // namespace vocal
