#pragma once
// Loading a YAML file with the project's error messages: what every config reader starts with.

#include <string>

#include <yaml-cpp/yaml.h>

namespace vocal {

// Throws InputError "PATH: cannot open WHAT" or "PATH: not valid YAML (...)".
YAML::Node loadYamlFile(const std::string& path, const std::string& what);

}  // namespace vocal
