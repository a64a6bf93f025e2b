#include "vocal/simulation/synthetic_sequence.h"

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <random>

#include "vocal/core/camera_yaml.h"
#include "vocal/core/errors.h"
#include "vocal/core/folders.h"
#include "vocal/core/gravity.h"
#include "vocal/core/image_io.h"
#include "vocal/core/se3.h"
#include "vocal/simulation/simulated_accelerometer.h"

namespace vocal {

namespace {
// Views averaged over an exposure (motion blur): enough that a 3 rad/s turn's 20 ms smear has no steps.
constexpr int kExposureInstants = 9;
std::string stampName(double stamp) {
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), "%.6f", stamp);
  return buffer;
}
}  // namespace

RgbdFrame renderSyntheticFrame(const SyntheticScene& scene, const PinholeCamera& camera,
                               const StampedPose& world_from_camera, const RgbdSensorModel& sensor_model,
                               std::uint32_t noise_seed) {
  RenderedView view = scene.render(camera, world_from_camera.pose);
  applyDepthSensorModel(sensor_model, noise_seed, &view.depth);
  applyColorSensorModel(sensor_model, noise_seed, &view.color);
  RgbdFrame frame;
  frame.stamp = world_from_camera.stamp;
  frame.color = std::move(view.color);
  frame.depth = std::move(view.depth);
  return frame;
}

RgbdFrame renderRollingShutterFrame(const SyntheticScene& scene, const PinholeCamera& camera, const Trajectory& path,
                                    std::size_t index, double readout_seconds, const RgbdSensorModel& sensor_model,
                                    std::uint32_t noise_seed, double exposure_seconds) {
  // The pose at `stamp`, between the path's samples; beyond its ends the first or last step goes on
  // (held there, the first and last frames' outer rows showed a camera stopping mid-readout).
  auto poseAt = [&](double stamp) {
    if (path.size() < 2) return path.at(index).pose;
    std::size_t k = std::min(index, path.size() - 2);
    while (k > 0 && path[k].stamp > stamp) --k;
    while (k + 2 < path.size() && path[k + 1].stamp <= stamp) ++k;
    const double alpha = (stamp - path[k].stamp) / (path[k + 1].stamp - path[k].stamp);
    return interpolatePose(path[k].pose, path[k + 1].pose, alpha);
  };
  constexpr int kBandRows = 4;  // rows exposed at one instant (0.25 ms apart at 30 ms over 480 rows)
  // A row's exposure: its colour the mean of kExposureInstants views spread over it (motion blur). Its
  // depth: the mean where every view saw a surface within 2 % of their mean, else none (a structured-light
  // pattern smeared across depths does not decode).
  const int instants = exposure_seconds > 0.0 ? kExposureInstants : 1;
  RgbdFrame frame;
  frame.stamp = path.at(index).stamp;
  frame.color = ColorImage(camera.width, camera.height);
  frame.depth = DepthImage(camera.width, camera.height, 0.0f);
  std::vector<Eigen::Vector3d> colour(static_cast<std::size_t>(camera.width) * kBandRows);
  std::vector<double> depth_sum(colour.size()), depth_min(colour.size()), depth_max(colour.size());
  for (int first = 0; first < camera.height; first += kBandRows) {
    const int rows = std::min(kBandRows, camera.height - first);
    PinholeCamera band = camera;  // the same camera cropped to the band's rows
    band.height = rows;
    band.cy = camera.cy - first;
    const double middle_row = first + 0.5 * (rows - 1);
    const double stamp = frame.stamp + readout_seconds * (middle_row / camera.height - 0.5);
    std::fill(colour.begin(), colour.end(), Eigen::Vector3d::Zero());
    std::fill(depth_sum.begin(), depth_sum.end(), 0.0);
    std::fill(depth_min.begin(), depth_min.end(), std::numeric_limits<double>::infinity());
    std::fill(depth_max.begin(), depth_max.end(), 0.0);
    for (int k = 0; k < instants; ++k) {
      const double offset = instants > 1 ? exposure_seconds * ((k + 0.5) / instants - 0.5) : 0.0;
      const RenderedView view = scene.render(band, poseAt(stamp + offset));
      for (int y = 0; y < rows; ++y) {
        for (int x = 0; x < camera.width; ++x) {
          const std::size_t i = static_cast<std::size_t>(y) * camera.width + x;
          const Rgb8 c = view.color(x, y);
          colour[i] += Eigen::Vector3d(c.r, c.g, c.b);
          const double z = view.depth(x, y);
          depth_sum[i] += z;
          depth_min[i] = std::min(depth_min[i], z);
          depth_max[i] = std::max(depth_max[i], z);
        }
      }
    }
    for (int y = 0; y < rows; ++y) {
      for (int x = 0; x < camera.width; ++x) {
        const std::size_t i = static_cast<std::size_t>(y) * camera.width + x;
        const Eigen::Vector3d c = colour[i] / instants;
        frame.color(x, first + y) = {static_cast<std::uint8_t>(std::lround(c.x())), static_cast<std::uint8_t>(std::lround(c.y())),
                                     static_cast<std::uint8_t>(std::lround(c.z()))};
        const double mean = depth_sum[i] / instants;
        const bool decoded = depth_min[i] > 0.0 && depth_max[i] - depth_min[i] <= 0.02 * mean;
        frame.depth(x, first + y) = decoded ? static_cast<float>(mean) : 0.0f;
      }
    }
  }
  applyDepthSensorModel(sensor_model, noise_seed, &frame.depth);
  applyColorSensorModel(sensor_model, noise_seed, &frame.color);
  return frame;
}

void coverLens(std::uint32_t noise_seed, RgbdFrame* frame) {
  std::mt19937 rng(noise_seed);
  std::normal_distribution<float> noise(0.0f, 2.0f);
  for (float& z : frame->depth.pixels()) z = 0.0f;
  for (Rgb8& p : frame->color.pixels()) {
    // Skin lit through the fingers: dark red-brown, a level or two of noise.
    auto level = [&](float mean) { return static_cast<std::uint8_t>(std::clamp(mean + noise(rng), 0.0f, 255.0f)); };
    p = {level(38.0f), level(24.0f), level(20.0f)};
  }
}

SyntheticSequence writeSyntheticSequence(const std::string& folder, const SyntheticSequenceOptions& options,
                                         const std::function<void(int, int)>& progress) {
  if (options.width < 8 || options.height < 8) {
    throw InputError("synthetic sequence: image size " + std::to_string(options.width) + "x" +
                     std::to_string(options.height) + " is too small (at least 8x8)");
  }
  if (options.covered_from < 0 || options.covered_frames < 0) {
    throw InputError("synthetic sequence: the covered stretch (from " + std::to_string(options.covered_from) + ", " +
                     std::to_string(options.covered_frames) + " frames) must not be negative");
  }
  if (!(options.exposure >= 0.0 && options.exposure <= 0.1)) {
    throw InputError("synthetic sequence: exposure " + std::to_string(options.exposure) + " s is not within [0, 0.1]");
  }
  if (!(options.rolling_shutter_readout >= 0.0 && options.rolling_shutter_readout <= 0.1)) {
    throw InputError("synthetic sequence: rolling shutter readout " + std::to_string(options.rolling_shutter_readout) +
                     " s must be in [0, 0.1]");
  }
  if (!(options.sensor_model.missing_fraction >= 0.0 && options.sensor_model.missing_fraction < 1.0)) {
    throw InputError("synthetic sequence: missing fraction " + std::to_string(options.sensor_model.missing_fraction) +
                     " must be in [0, 1)");
  }
  const SyntheticScene scene = SyntheticScene::make(options.scene);
  SyntheticSequence sequence;
  sequence.camera = defaultKinectCamera(options.width, options.height);
  sequence.ground_truth = !options.trajectory_path.empty() ? readTumTrajectory(options.trajectory_path)
                          : !options.poses.empty()        ? options.poses
                                                          : generateSyntheticTrajectory(scene.workspace(), options.trajectory);
  if (sequence.ground_truth.empty()) {
    throw InputError(options.trajectory_path + ": trajectory has no poses");
  }

  makeFolders(folder);
  makeFolders(folder + "/rgb");
  makeFolders(folder + "/depth");
  writeCameraYaml(folder + "/camera.yaml", sequence.camera, "vocal_synthetic_" + sceneVariantName(options.scene));
  writeTumTrajectory(folder + "/groundtruth.txt", sequence.ground_truth);
  // A Kinect's accelerometer (0.05 m/s^2 of noise, about its resolution): what levels the odometry's frame.
  writeAccelerometerFile(folder + "/accelerometer.txt", simulateKinectAccelerometer(sequence.ground_truth, 0.05, 7));

  std::ofstream rgb_list(folder + "/rgb.txt");
  std::ofstream depth_list(folder + "/depth.txt");
  if (!rgb_list || !depth_list) {
    throw InputError(folder + ": cannot write rgb.txt / depth.txt");
  }
  const std::string header = "# vocal synthetic sequence, scene " + sceneVariantName(options.scene) + "\n";
  rgb_list << header << "# timestamp filename\n";
  depth_list << header << "# timestamp filename\n";
  const int total = static_cast<int>(sequence.ground_truth.size());
  for (int i = 0; i < total; ++i) {
    const StampedPose& pose = sequence.ground_truth[i];
    const std::uint32_t noise_seed = options.trajectory.seed * 100003u + static_cast<std::uint32_t>(i);
    RgbdFrame frame = options.rolling_shutter_readout > 0.0 || options.exposure > 0.0
                          ? renderRollingShutterFrame(scene, sequence.camera, sequence.ground_truth, static_cast<std::size_t>(i),
                                                      options.rolling_shutter_readout, options.sensor_model, noise_seed,
                                                      options.exposure)
                          : renderSyntheticFrame(scene, sequence.camera, pose, options.sensor_model, noise_seed);
    if (i >= options.covered_from && i < options.covered_from + options.covered_frames) coverLens(noise_seed, &frame);
    const std::string name = stampName(pose.stamp) + ".png";
    writeColorPng(folder + "/rgb/" + name, frame.color);
    writeDepthPng(folder + "/depth/" + name, frame.depth, sequence.camera.depth_scale);
    rgb_list << stampName(pose.stamp) << " rgb/" << name << "\n";
    depth_list << stampName(pose.stamp) << " depth/" << name << "\n";
    if (progress) progress(i + 1, total);
  }
  if (!rgb_list.flush() || !depth_list.flush()) {
    throw InputError(folder + ": write error on rgb.txt / depth.txt");
  }
  return sequence;
}

}  // namespace vocal
