#include "vocal/odometry/odometry_config_yaml.h"

#include <functional>
#include <map>

#include <yaml-cpp/yaml.h>

#include "vocal/core/errors.h"
#include "vocal/core/yaml_file.h"

namespace vocal {

OdometryConfig readOdometryConfigYaml(const std::string& path, const OdometryConfig& defaults) {
  return odometryConfigFromYaml(loadYamlFile(path, "odometry config"), path, defaults, false);
}

OdometryConfig odometryConfigFromYaml(const YAML::Node& root, const std::string& path, const OdometryConfig& defaults,
                                      bool ignore_other_keys) {
  OdometryConfig config = defaults;
  using Setter = std::function<void(const YAML::Node&)>;
  const std::map<std::string, Setter> setters = {
      {"mode", [&](const YAML::Node& n) { config.mode = parseOdometryMode(n.as<std::string>()); }},
      {"levels", [&](const YAML::Node& n) { config.levels = n.as<int>(); }},
      {"iterations", [&](const YAML::Node& n) { config.iterations = n.as<std::vector<int>>(); }},
      {"convergence_translation", [&](const YAML::Node& n) { config.convergence_translation = n.as<double>(); }},
      {"convergence_rotation", [&](const YAML::Node& n) { config.convergence_rotation = n.as<double>(); }},
      {"finest_convergence_factor", [&](const YAML::Node& n) { config.finest_convergence_factor = n.as<double>(); }},
      {"icp_max_distance", [&](const YAML::Node& n) { config.icp_max_distance = n.as<double>(); }},
      {"icp_max_angle_deg", [&](const YAML::Node& n) { config.icp_max_angle_deg = n.as<double>(); }},
      {"depth_pyramid_sigma", [&](const YAML::Node& n) { config.depth_pyramid_sigma = n.as<double>(); }},
      {"depth_smoothing_radius", [&](const YAML::Node& n) { config.depth_smoothing_radius = n.as<int>(); }},
      {"depth_smoothing_factor", [&](const YAML::Node& n) { config.depth_smoothing_factor = n.as<double>(); }},
      {"depth_noise_floor", [&](const YAML::Node& n) { config.depth_noise_floor = n.as<double>(); }},
      {"depth_noise_quadratic", [&](const YAML::Node& n) { config.depth_noise_quadratic = n.as<double>(); }},
      {"rgb_max_depth", [&](const YAML::Node& n) { config.rgb_max_depth = n.as<double>(); }},
      {"rgb_max_depth_difference", [&](const YAML::Node& n) { config.rgb_max_depth_difference = n.as<double>(); }},
      {"rgb_min_gradient", [&](const YAML::Node& n) { config.rgb_min_gradient = n.as<std::vector<double>>(); }},
      {"rgb_huber_factor", [&](const YAML::Node& n) { config.rgb_huber_factor = n.as<double>(); }},
      {"brightness_model", [&](const YAML::Node& n) { config.brightness_model = parseBrightnessModel(n.as<std::string>()); }},
      {"undistort_lens", [&](const YAML::Node& n) { config.undistort_lens = n.as<bool>(); }},
      {"rolling_shutter_readout", [&](const YAML::Node& n) { config.rolling_shutter_readout = n.as<double>(); }},
      {"depth_time_offset", [&](const YAML::Node& n) { config.depth_time_offset = n.as<double>(); }},
      {"rgb_weight", [&](const YAML::Node& n) { config.rgb_weight = n.as<double>(); }},
      {"imu_weight", [&](const YAML::Node& n) { config.imu_weight = n.as<double>(); }},
      {"gravity_time_constant", [&](const YAML::Node& n) { config.gravity_time_constant = n.as<double>(); }},
      {"feature_initialisation",
       [&](const YAML::Node& n) { config.feature_initialisation = parseFeatureInitialisation(n.as<std::string>()); }},
      {"feature_fallback_residual_ratio",
       [&](const YAML::Node& n) { config.feature_fallback_residual_ratio = n.as<double>(); }},
      {"tracking_reference",
       [&](const YAML::Node& n) { config.tracking_reference = parseTrackingReference(n.as<std::string>()); }},
      {"keyframe_min_overlap", [&](const YAML::Node& n) { config.keyframe_min_overlap = n.as<double>(); }},
      {"keyframe_max_residual_growth", [&](const YAML::Node& n) { config.keyframe_max_residual_growth = n.as<double>(); }},
      {"keyframe_max_translation", [&](const YAML::Node& n) { config.keyframe_max_translation = n.as<double>(); }},
      {"keyframe_max_rotation_deg", [&](const YAML::Node& n) { config.keyframe_max_rotation_deg = n.as<double>(); }},
      {"keyframe_after_unconverged", [&](const YAML::Node& n) { config.keyframe_after_unconverged = n.as<bool>(); }},
      {"keyframes_kept", [&](const YAML::Node& n) { config.keyframes_kept = n.as<int>(); }},
      {"local_window_keyframes", [&](const YAML::Node& n) { config.local_window_keyframes = n.as<int>(); }},
      {"local_window_links", [&](const YAML::Node& n) { config.local_window_links = n.as<int>(); }},
      {"local_window_background", [&](const YAML::Node& n) { config.local_window_background = n.as<bool>(); }},
      {"max_predicted_frames", [&](const YAML::Node& n) { config.max_predicted_frames = n.as<int>(); }},
      {"relocalisation", [&](const YAML::Node& n) { config.relocalisation = n.as<bool>(); }},
      {"wrong_minimum_residual_ratio", [&](const YAML::Node& n) { config.wrong_minimum_residual_ratio = n.as<double>(); }},
      {"wrong_minimum_feature_translation",
       [&](const YAML::Node& n) { config.wrong_minimum_feature_translation = n.as<double>(); }},
      {"wrong_minimum_feature_rotation_deg",
       [&](const YAML::Node& n) { config.wrong_minimum_feature_rotation_deg = n.as<double>(); }},
      {"min_depth", [&](const YAML::Node& n) { config.min_depth = n.as<double>(); }},
      {"max_depth", [&](const YAML::Node& n) { config.max_depth = n.as<double>(); }},
      {"max_translation", [&](const YAML::Node& n) { config.max_translation = n.as<double>(); }},
      {"max_rotation_deg", [&](const YAML::Node& n) { config.max_rotation_deg = n.as<double>(); }},
      {"min_icp_inliers", [&](const YAML::Node& n) { config.min_icp_inliers = n.as<int>(); }},
      {"min_rgb_inliers", [&](const YAML::Node& n) { config.min_rgb_inliers = n.as<int>(); }},
      {"max_condition", [&](const YAML::Node& n) { config.max_condition = n.as<double>(); }},
      {"backend", [&](const YAML::Node& n) { config.backend = parseOdometryBackend(n.as<std::string>()); }},
      {"keep_pace_max_level", [&](const YAML::Node& n) { config.keep_pace_max_level = n.as<int>(); }},
      {"keep_pace_row_step", [&](const YAML::Node& n) { config.keep_pace_row_step = n.as<int>(); }},
      {"keep_pace_refines_keyframes", [&](const YAML::Node& n) { config.keep_pace_refines_keyframes = n.as<bool>(); }},
      {"threads", [&](const YAML::Node& n) { config.threads = n.as<int>(); }},
      {"cpu_threads", [&](const YAML::Node& n) { config.threads = n.as<int>(); }},  // the name before 'threads'
      {"opencl_platform", [&](const YAML::Node& n) { config.opencl_platform = n.as<std::string>(); }},
      {"opencl_device", [&](const YAML::Node& n) { config.opencl_device = n.as<std::string>(); }},
  };
  if (!root.IsMap() && !root.IsNull()) {
    throw InputError(path + ": expected a map of odometry settings");
  }
  for (const auto& entry : root) {
    const std::string key = yamlKeyName(entry.first, path);
    const auto setter = setters.find(key);
    if (setter == setters.end()) {
      if (ignore_other_keys) continue;
      throw InputError(path + ": unknown odometry setting '" + key + "'");
    }
    try {
      setter->second(entry.second);
    } catch (const YAML::Exception& e) {
      throw InputError(path + ": setting '" + key + "' is malformed (" + e.what() + ")");
    } catch (const InputError& e) {
      throw InputError(path + ": " + e.what());
    }
  }
  try {
    config.validate();
  } catch (const InputError& e) {
    throw InputError(path + ": " + e.what());
  }
  return config;
}

}  // namespace vocal
