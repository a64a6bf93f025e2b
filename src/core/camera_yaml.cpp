#include "vocal/core/camera_yaml.h"

#include <fstream>
#include <iomanip>

#include <yaml-cpp/yaml.h>

#include "vocal/core/errors.h"
#include "vocal/core/yaml_file.h"

namespace vocal {

namespace {
template <typename T>
T required(const YAML::Node& root, const std::string& path, const std::string& key) {
  const YAML::Node node = root[key];
  if (!node) {
    throw InputError(path + ": missing key '" + key + "'");
  }
  try {
    return node.as<T>();
  } catch (const YAML::Exception& e) {
    throw InputError(path + ": key '" + key + "' is malformed (" + e.what() + ")");
  }
}
}  // namespace

PinholeCamera readCameraYaml(const std::string& path) {
  const YAML::Node root = loadYamlFile(path, "camera file");
  if (!root.IsMap()) throw InputError(path + ": expected a map of camera_info keys (image_width, camera_matrix, ...)");
  PinholeCamera camera;
  camera.width = required<int>(root, path, "image_width");
  camera.height = required<int>(root, path, "image_height");
  const YAML::Node matrix = root["camera_matrix"];
  if (!matrix) {
    throw InputError(path + ": missing key 'camera_matrix'");
  }
  if (!matrix.IsMap()) throw InputError(path + ": camera_matrix must be a map with rows, cols and data");
  const auto k = required<std::vector<double>>(matrix, path, "data");
  if (k.size() != 9) {
    throw InputError(path + ": camera_matrix.data has " + std::to_string(k.size()) + " values, expected 9");
  }
  camera.fx = k[0];
  camera.cx = k[2];
  camera.fy = k[4];
  camera.cy = k[5];
  if (root["depth_scale"]) {
    camera.depth_scale = required<double>(root, path, "depth_scale");
  }
  camera.validate(path);
  return camera;
}

void writeCameraYaml(const std::string& path, const PinholeCamera& camera, const std::string& camera_name) {
  std::ofstream file(path);
  if (!file) {
    throw InputError(path + ": cannot write camera file");
  }
  file << std::setprecision(17);
  file << "image_width: " << camera.width << "\n"
       << "image_height: " << camera.height << "\n"
       << "camera_name: " << camera_name << "\n"
       << "camera_matrix:\n  rows: 3\n  cols: 3\n"
       << "  data: [" << camera.fx << ", 0, " << camera.cx << ", 0, " << camera.fy << ", " << camera.cy
       << ", 0, 0, 1]\n"
       << "distortion_model: plumb_bob\n"
       << "distortion_coefficients:\n  rows: 1\n  cols: 5\n  data: [0, 0, 0, 0, 0]\n"
       << "rectification_matrix:\n  rows: 3\n  cols: 3\n  data: [1, 0, 0, 0, 1, 0, 0, 0, 1]\n"
       << "projection_matrix:\n  rows: 3\n  cols: 4\n"
       << "  data: [" << camera.fx << ", 0, " << camera.cx << ", 0, 0, " << camera.fy << ", " << camera.cy
       << ", 0, 0, 0, 1, 0]\n"
       << "depth_scale: " << camera.depth_scale << "\n";
  if (!file) {
    throw InputError(path + ": write error");
  }
}

}  // namespace vocal
