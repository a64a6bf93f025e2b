#include "vocal/simulation/simulated_arm.h"

#include <cmath>

#include "vocal/core/se3.h"

namespace vocal {

namespace {
// A frame at `position` whose z axis points at `target`, turned `roll` about it.
Eigen::Isometry3d lookingAt(const Eigen::Vector3d& position, const Eigen::Vector3d& target, double roll) {
  const Eigen::Vector3d z = (target - position).normalized();
  const Eigen::Vector3d helper = std::abs(z.z()) < 0.9 ? Eigen::Vector3d::UnitZ() : Eigen::Vector3d::UnitX();
  const Eigen::Vector3d x = helper.cross(z).normalized();
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() << x, z.cross(x), z;
  pose.linear() = pose.linear() * Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  pose.translation() = position;
  return pose;
}

Eigen::Isometry3d perturbed(const Eigen::Isometry3d& pose, double translation_sigma, double rotation_sigma, std::mt19937* rng) {
  std::normal_distribution<double> normal(0.0, 1.0);
  Vector6d twist;
  for (int i = 0; i < 3; ++i) twist[i] = translation_sigma * normal(*rng);
  for (int i = 3; i < 6; ++i) twist[i] = rotation_sigma * normal(*rng);
  Eigen::Isometry3d noisy = pose;
  noisy.translation() += twist.head<3>();
  noisy.linear() = pose.linear() * Eigen::AngleAxisd(twist.tail<3>().norm(), twist.tail<3>().norm() > 0 ? twist.tail<3>().normalized()
                                                                                                         : Eigen::Vector3d::UnitX())
                                        .toRotationMatrix();
  return noisy;
}
}  // namespace

Eigen::Isometry3d SimulatedArm::cameraFromBoard(int k) const {
  return setup == HandEyeSetup::kEyeInHand ? camera.inverse() * true_tool[k].inverse() * board : camera.inverse() * true_tool[k] * board;
}

SimulatedArm simulateArm(const SimulatedArmOptions& options) {
  std::mt19937 rng(options.seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  SimulatedArm arm;
  arm.setup = options.setup;
  // A camera on a wrist: beside the flange, looking along the tool's z, turned a quarter about it.
  const Eigen::Isometry3d tool_from_camera =
      poseFromTranslationQuaternion({0.055, -0.035, -0.042}, Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ())));
  // A board in a gripper: 12 cm past the flange, facing along the tool's z.
  const Eigen::Isometry3d tool_from_board =
      poseFromTranslationQuaternion({0.01, 0.02, 0.12}, Eigen::Quaterniond(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ())));
  if (options.setup == HandEyeSetup::kEyeInHand) {
    arm.camera = tool_from_camera;
    // On the table, its z axis down: a camera above looks along it.
    arm.board = poseFromTranslationQuaternion({0.5, 0.0, 0.0}, Eigen::Quaterniond(Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX())));
    // A 2D laser 6 cm beside the camera, its x along the tool's z (down at the board), its scan plane
    // holding the tool's z and turned 0.15 rad about it: the line crosses the board at a slant.
    arm.laser = poseFromTranslationQuaternion({-0.06, 0.02, 0.0}, Eigen::Quaterniond(Eigen::AngleAxisd(-M_PI / 2, Eigen::Vector3d::UnitY()) *
                                                                                      Eigen::AngleAxisd(0.15, Eigen::Vector3d::UnitX())));
  } else {
    arm.camera = lookingAt({0.5, 0.9, 0.6}, {0.5, 0.0, 0.3}, 0.0);  // on a post beside the arm, looking at its workspace
    arm.board = tool_from_board;
    // Where a robot's body carries them: a lidar across the workspace, level, and an RGB-D camera beside it.
    arm.lidar = poseFromTranslationQuaternion({0.55, 1.35, 0.35}, Eigen::Quaterniond(Eigen::AngleAxisd(-M_PI / 2 - 0.05, Eigen::Vector3d::UnitZ())));
    arm.rgbd = lookingAt({0.05, 0.85, 0.55}, {0.5, 0.0, 0.3}, 0.0);
    // A 2D laser on a post at the board's height, its scan plane rolled a little: it crosses the board
    // in the gripper at most poses.
    arm.laser = poseFromTranslationQuaternion({0.45, 1.0, 0.37}, Eigen::Quaterniond(Eigen::AngleAxisd(-M_PI / 2, Eigen::Vector3d::UnitZ()) *
                                                                                     Eigen::AngleAxisd(0.08, Eigen::Vector3d::UnitX())));
  }
  for (int k = 0; k < options.poses; ++k) {
    Eigen::Isometry3d tool;
    if (options.setup == HandEyeSetup::kEyeInHand) {
      // The camera on a hemisphere above the board, looking at a point near its centre.
      const double distance = 0.6 + 0.1 * unit(rng);
      const Eigen::Vector3d from = Eigen::AngleAxisd(options.tilt * unit(rng), Eigen::Vector3d::UnitX()) *
                                   Eigen::AngleAxisd(options.tilt * unit(rng), Eigen::Vector3d::UnitY()) * Eigen::Vector3d(0, 0, distance);
      const Eigen::Vector3d centre = arm.board.translation() + Eigen::Vector3d(0.03 * unit(rng), 0.03 * unit(rng), 0.0);
      tool = lookingAt(centre + from, centre, options.roll * unit(rng)) * tool_from_camera.inverse();
    } else {
      // The board near_depth-far_depth from the camera, facing it (its z away from the camera), tilted.
      // (Drawn in the order the sessions before near_depth drew them.)
      const double depth = 0.5 * (options.near_depth + options.far_depth) + 0.5 * (options.far_depth - options.near_depth) * unit(rng);
      const double up = 0.1 * unit(rng);
      const double across = 0.1 * unit(rng);
      Eigen::Vector3d centre = arm.camera * Eigen::Vector3d(across, up, depth);
      if (options.across_laser) centre.z() = arm.laser.translation().z() + up;
      Eigen::Isometry3d board = lookingAt(centre, centre + (centre - arm.camera.translation()), options.roll * unit(rng));
      board.linear() = board.linear() * (Eigen::AngleAxisd(options.tilt * unit(rng), Eigen::Vector3d::UnitX()) *
                                         Eigen::AngleAxisd(options.tilt * unit(rng), Eigen::Vector3d::UnitY()))
                                            .toRotationMatrix();
      tool = board * tool_from_board.inverse();
    }
    arm.true_tool.push_back(tool);
    Eigen::Isometry3d reported = perturbed(tool, options.tool_translation_noise, options.tool_rotation_noise, &rng);
    if (k == options.poor_pose) {
      const Eigen::Vector3d direction = Eigen::Vector3d(unit(rng), unit(rng), unit(rng)).normalized();
      reported.translation() += options.poor_pose_offset * direction;
    }
    arm.reported_tool.push_back(reported);
  }
  return arm;
}

std::vector<HandEyeStation> simulateHandEyeStations(const SimulatedArm& arm, const TargetPattern& pattern, const PinholeCamera& camera,
                                                    int views, double pixel_noise, std::mt19937* rng, const PinholeCamera* camera_info) {
  std::normal_distribution<double> noise(0.0, pixel_noise);
  const std::vector<Eigen::Vector3d> corners = pattern.corners();
  std::vector<HandEyeStation> stations;
  for (std::size_t k = 0; k < arm.true_tool.size(); ++k) {
    HandEyeStation station;
    station.base_from_tool = arm.reported_tool[k];
    station.first_stamp = 3.0 * static_cast<double>(k);
    station.last_stamp = station.first_stamp + 0.1 * (views - 1);
    const Eigen::Isometry3d camera_from_board = arm.cameraFromBoard(static_cast<int>(k));
    for (int v = 0; v < views; ++v) {
      std::vector<Eigen::Vector2d> pixels;
      for (const Eigen::Vector3d& c : corners) pixels.push_back(camera.project(camera_from_board * c) + Eigen::Vector2d(noise(*rng), noise(*rng)));
      station.views.push_back({0, observePattern(pixels, pattern, camera_info ? *camera_info : camera, "simulated arm camera").plane, {}, {}});
    }
    stations.push_back(std::move(station));
  }
  return stations;
}

std::vector<Eigen::Vector3d> simulateRangeView(const SimulatedArm& arm, int k, const Eigen::Isometry3d& base_from_sensor, double width,
                                               double height, double spacing, double noise, std::mt19937* rng) {
  std::normal_distribution<double> along_ray(0.0, noise);
  const Eigen::Isometry3d base_from_board = arm.setup == HandEyeSetup::kEyeInHand ? arm.board : arm.true_tool[k] * arm.board;
  const Eigen::Isometry3d sensor_from_board = base_from_sensor.inverse() * base_from_board;
  std::vector<Eigen::Vector3d> points;
  for (double x = -width / 2; x <= width / 2; x += spacing) {
    for (double y = -height / 2; y <= height / 2; y += spacing) {
      const Eigen::Vector3d p = sensor_from_board * Eigen::Vector3d(x, y, 0.0);
      points.push_back(p + along_ray(*rng) * p.normalized());
    }
  }
  return points;
}

}  // namespace vocal
