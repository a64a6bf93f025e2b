#pragma once
// Loading a YAML file with the project's error messages: what every config reader starts with.

#include <string>

#include <yaml-cpp/yaml.h>

namespace vocal {

// Throws InputError "PATH: cannot open WHAT" or "PATH: not valid YAML (...)".
YAML::Node loadYamlFile(const std::string& path, const std::string& what);

// A map key's name. A key that is a list or map (`[a]: 1`, valid YAML) is not a setting's name: throws
// InputError "WHERE: line N: a key is a list or map, not a name".
std::string yamlKeyName(const YAML::Node& key, const std::string& where);

}  // namespace vocal
