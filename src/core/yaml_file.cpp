#include "vocal/core/yaml_file.h"

#include "vocal/core/errors.h"

namespace vocal {

YAML::Node loadYamlFile(const std::string& path, const std::string& what) {
  try {
    return YAML::LoadFile(path);
  } catch (const YAML::BadFile&) {
    throw InputError(path + ": cannot open " + what);
  } catch (const YAML::Exception& e) {
    throw InputError(path + ": not valid YAML (" + e.what() + ")");
  }
}

std::string yamlKeyName(const YAML::Node& key, const std::string& where) {
  if (!key.IsScalar()) throw InputError(where + ": line " + std::to_string(key.Mark().line + 1) + ": a key is a list or map, not a name");
  return key.Scalar();
}

}  // namespace vocal
