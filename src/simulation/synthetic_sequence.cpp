#include "vocal/simulation/synthetic_sequence.h"

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <random>

#include "vocal/core/camera_yaml.h"
#include "vocal/core/errors.h"
#include "vocal/core/folders.h"
#include "vocal/core/image_io.h"

namespace vocal {

namespace {
std::string stampName(double stamp) {
  char buffer[64];
  std::snprintf(buffer, sizeof(buffer), "%.6f", stamp);
  return buffer;
}
}  // namespace

RgbdSensorModel kinectLikeSensorModel(double missing_fraction) {
  RgbdSensorModel model;
  model.color_noise_sigma = 2.0;
  model.axial_noise = true;
  model.quantize_disparity = true;
  model.missing_fraction = missing_fraction;
  model.drop_discontinuities = true;
  return model;
}

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
  if (!(options.sensor_model.missing_fraction >= 0.0 && options.sensor_model.missing_fraction < 1.0)) {
    throw InputError("synthetic sequence: missing fraction " + std::to_string(options.sensor_model.missing_fraction) +
                     " must be in [0, 1)");
  }
  const SyntheticScene scene = SyntheticScene::make(options.scene);
  SyntheticSequence sequence;
  sequence.camera = defaultKinectCamera(options.width, options.height);
  sequence.ground_truth = options.trajectory_path.empty()
                              ? generateSyntheticTrajectory(scene.workspace(), options.trajectory)
                              : readTumTrajectory(options.trajectory_path);
  if (sequence.ground_truth.empty()) {
    throw InputError(options.trajectory_path + ": trajectory has no poses");
  }

  makeFolders(folder);
  makeFolders(folder + "/rgb");
  makeFolders(folder + "/depth");
  writeCameraYaml(folder + "/camera.yaml", sequence.camera, "vocal_synthetic_" + sceneVariantName(options.scene));
  writeTumTrajectory(folder + "/groundtruth.txt", sequence.ground_truth);

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
    RgbdFrame frame = renderSyntheticFrame(scene, sequence.camera, pose, options.sensor_model, noise_seed);
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
