#include "vocal/odometry/odometry_config.h"

#include <algorithm>
#include <cmath>

#include "vocal/core/errors.h"

namespace vocal {

void OdometryConfig::validate() const {
  auto fail = [](const std::string& what) { throw InputError("odometry config: " + what); };
  if (levels < 1 || levels > 6) fail("levels must be in [1, 6], got " + std::to_string(levels));
  if (static_cast<int>(iterations.size()) != levels)
    fail("iterations lists " + std::to_string(iterations.size()) + " values for " + std::to_string(levels) + " levels");
  if (static_cast<int>(rgb_min_gradient.size()) != levels)
    fail("rgb_min_gradient lists " + std::to_string(rgb_min_gradient.size()) + " values for " +
         std::to_string(levels) + " levels");
  for (int n : iterations)
    if (n < 0) fail("iterations must not be negative");
  if (!(icp_max_distance > 0.0)) fail("icp_max_distance must be positive");
  if (!(icp_max_angle_deg > 0.0 && icp_max_angle_deg <= 180.0)) fail("icp_max_angle_deg must be in (0, 180]");
  if (!(rgb_weight >= 0.0 && std::isfinite(rgb_weight))) fail("rgb_weight must be finite and >= 0");
  if (!(imu_weight >= 0.0 && std::isfinite(imu_weight))) fail("imu_weight must be finite and >= 0");
  if (!(gravity_time_constant >= 0.0 && std::isfinite(gravity_time_constant))) fail("gravity_time_constant must be finite and >= 0");
  if (!(feature_fallback_residual_ratio > 1.0 && std::isfinite(feature_fallback_residual_ratio)))
    fail("feature_fallback_residual_ratio must be finite and > 1");
  if (!(keyframe_min_overlap >= 0.0 && keyframe_min_overlap <= 1.0)) fail("keyframe_min_overlap must be in [0, 1]");
  if (!(keyframe_max_residual_growth > 1.0)) fail("keyframe_max_residual_growth must be > 1");
  if (!(keyframe_max_translation > 0.0)) fail("keyframe_max_translation must be positive");
  if (!(keyframe_max_rotation_deg > 0.0)) fail("keyframe_max_rotation_deg must be positive");
  if (keyframes_kept < 1 || keyframes_kept > 1000) fail("keyframes_kept must be in [1, 1000], got " + std::to_string(keyframes_kept));
  if (!(finest_convergence_factor > 0.0) || !std::isfinite(finest_convergence_factor))
    fail("finest_convergence_factor must be a positive number (1: the coarse levels' thresholds)");
  if (local_window_keyframes != 0 && (local_window_keyframes < 2 || local_window_keyframes > 50))
    fail("local_window_keyframes must be 0 (no window) or in [2, 50], got " + std::to_string(local_window_keyframes));
  if (local_window_keyframes > keyframes_kept)
    fail("local_window_keyframes (" + std::to_string(local_window_keyframes) + ") must not exceed keyframes_kept (" +
         std::to_string(keyframes_kept) + "): the window refines kept keyframes");
  if (local_window_links < 1) fail("local_window_links must be at least 1, got " + std::to_string(local_window_links));
  if (max_predicted_frames < 0) fail("max_predicted_frames must not be negative");
  if (!(wrong_minimum_residual_ratio > 1.0)) fail("wrong_minimum_residual_ratio must be > 1");
  if (!(wrong_minimum_feature_translation > 0.0)) fail("wrong_minimum_feature_translation must be positive");
  if (!(wrong_minimum_feature_rotation_deg > 0.0)) fail("wrong_minimum_feature_rotation_deg must be positive");
  if (!(min_depth >= 0.0 && max_depth > min_depth)) fail("depth range [min_depth, max_depth] is empty");
  if (depth_smoothing_radius < 0 || depth_smoothing_radius > 10) fail("depth_smoothing_radius must be in [0, 10]");
  if (!(depth_smoothing_factor > 0.0)) fail("depth_smoothing_factor must be positive");
  if (!(depth_noise_floor > 0.0 && depth_noise_floor < 1.0)) fail("depth_noise_floor must be in (0, 1) metres");
  if (!(depth_noise_quadratic >= 0.0 && depth_noise_quadratic < 1.0))
    fail("depth_noise_quadratic must be in [0, 1) per metre (0 = every ICP pair weighted alike)");
  if (!(max_translation > 0.0)) fail("max_translation must be positive");
  if (!(rolling_shutter_readout >= 0.0 && rolling_shutter_readout <= 0.1))
    fail("rolling_shutter_readout must be in [0, 0.1] seconds (0 = global shutter)");
  if (!(std::fabs(depth_time_offset) <= 0.1)) fail("depth_time_offset must be in [-0.1, 0.1] seconds (0 = taken together)");
  if (keep_pace_max_level < 0 || keep_pace_max_level > 5)
    fail("keep_pace_max_level must be in [0, 5] (0: always the input's resolution), got " + std::to_string(keep_pace_max_level));
  for (int level = 1; level <= std::min(keep_pace_max_level, levels - 1); ++level) {
    if (iterations[level] <= 0)
      fail("keep_pace_max_level " + std::to_string(keep_pace_max_level) + " needs iterations at level " + std::to_string(level) +
           " (it may be tracked as the finest), got " + std::to_string(iterations[level]));
  }
  if (keep_pace_row_step < 1 || keep_pace_row_step > kMaxFinestRowStep) {
    fail("keep_pace_row_step must be in [1, " + std::to_string(kMaxFinestRowStep) + "] (1: every row), got " +
         std::to_string(keep_pace_row_step));
  }
  if (threads < 0 || threads > 256) fail("threads must be in [0, 256] (0 = OMP_NUM_THREADS or the cores), got " + std::to_string(threads));
}

OdometryMode parseOdometryMode(const std::string& name) {
  if (name == "icp") return OdometryMode::kIcp;
  if (name == "rgb") return OdometryMode::kRgb;
  if (name == "fused") return OdometryMode::kFused;
  throw InputError("odometry mode '" + name + "' is unknown: expected icp, rgb or fused");
}

std::string odometryModeName(OdometryMode mode) {
  switch (mode) {
    case OdometryMode::kIcp: return "icp";
    case OdometryMode::kRgb: return "rgb";
    case OdometryMode::kFused: return "fused";
  }
  return "unknown";
}

OdometryBackendKind parseOdometryBackend(const std::string& name) {
  if (name == "auto") return OdometryBackendKind::kAuto;
  if (name == "cpu") return OdometryBackendKind::kCpu;
  if (name == "reference") return OdometryBackendKind::kReference;
  if (name == "opencl") return OdometryBackendKind::kOpenCl;
  throw InputError("odometry backend '" + name + "' is unknown: expected auto, cpu, reference or opencl");
}

FeatureInitialisation parseFeatureInitialisation(const std::string& name) {
  // YAML booleans (the setting's earlier form) read as strings: true = always, false = off.
  if (name == "always" || name == "true") return FeatureInitialisation::kAlways;
  if (name == "fallback") return FeatureInitialisation::kFallback;
  if (name == "off" || name == "false") return FeatureInitialisation::kOff;
  throw InputError("feature initialisation '" + name + "' is unknown: expected always, fallback or off");
}

TrackingReference parseTrackingReference(const std::string& name) {
  if (name == "keyframe") return TrackingReference::kKeyframe;
  if (name == "frame") return TrackingReference::kFrame;
  throw InputError("tracking reference '" + name + "' is unknown: expected keyframe or frame");
}

BrightnessModel parseBrightnessModel(const std::string& name) {
  if (name == "affine") return BrightnessModel::kAffine;
  if (name == "fixed") return BrightnessModel::kFixed;
  throw InputError("brightness model '" + name + "' is unknown: expected affine or fixed");
}

}  // namespace vocal
