#include "vocal/simulation/rig_simulator.h"

#include <cmath>
#include <random>

#include "vocal/calibration/extraction/board_outline.h"
#include "vocal/calibration/point_statistics.h"
#include "vocal/core/pinhole_camera.h"

#include "vocal/core/errors.h"
#include "vocal/core/se3.h"

namespace vocal {

namespace {
Eigen::Isometry3d makePose(const Eigen::Vector3d& t, const Eigen::Matrix3d& R) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = R;
  pose.translation() = t;
  return pose;
}

// Rays of a sensor in its own frame: a Kinect-like pinhole grid, or a 16-ring lidar.
std::vector<Eigen::Vector3d> makeSensorRays(SensorType type) {
  std::vector<Eigen::Vector3d> rays;
  if (type == SensorType::kRgbd) {
    for (int v = 4; v < 480; v += 8)
      for (int u = 4; u < 640; u += 8) rays.push_back(Eigen::Vector3d((u - 319.5) / 525.0, (v - 239.5) / 525.0, 1.0).normalized());
  } else if (type == SensorType::kLaser2d) {
    for (int step = 0; step <= 1080; ++step) {
      const double azimuth = (-135.0 + 0.25 * step) * M_PI / 180.0;
      rays.push_back({std::cos(azimuth), std::sin(azimuth), 0.0});
    }
  } else if (type == SensorType::kLidar3d) {
    for (int ring = 0; ring < 16; ++ring) {
      const double elevation = (-15.0 + 2.0 * ring) * M_PI / 180.0;
      for (int step = 0; step < 1800; ++step) {
        const double azimuth = step * 0.2 * M_PI / 180.0 - M_PI;
        rays.push_back({std::cos(elevation) * std::cos(azimuth), std::cos(elevation) * std::sin(azimuth), std::sin(elevation)});
      }
    }
  }
  return rays;
}

// The ray sets are fixed per sensor type: built once, not per observation.
const std::vector<Eigen::Vector3d>& sensorRays(SensorType type) {
  static const std::vector<Eigen::Vector3d> rgbd = makeSensorRays(SensorType::kRgbd);
  static const std::vector<Eigen::Vector3d> lidar = makeSensorRays(SensorType::kLidar3d);
  static const std::vector<Eigen::Vector3d> laser = makeSensorRays(SensorType::kLaser2d);
  static const std::vector<Eigen::Vector3d> none;
  switch (type) {
    case SensorType::kRgbd: return rgbd;
    case SensorType::kLidar3d: return lidar;
    case SensorType::kLaser2d: return laser;
    case SensorType::kCamera: return none;  // cameras see the pattern's corners instead
  }
  return none;
}
}  // namespace

std::vector<SimulatedSensor> exampleRig(int rgbd_sensors, int lidar_sensors, int laser_sensors, int cameras) {
  std::vector<SimulatedSensor> sensors;
  for (int i = 0; i < rgbd_sensors; ++i) {
    SimulatedSensor s;
    s.spec = {"rgbd" + std::to_string(i), SensorType::kRgbd, "rgbd" + std::to_string(i) + "_optical_frame"};
    const double yaw = 0.15 * i * (i % 2 ? 1 : -1), pitch = 0.05 * i;
    s.reference_from_sensor = makePose(Eigen::Vector3d(0.1 * i, 0.25 * i * (i % 2 ? 1 : -1), 0.8 + 0.1 * i),
                                       rotationFromRollPitchYaw(0.02 * i, pitch, yaw) * bodyFromOpticalRotation());
    sensors.push_back(s);
  }
  for (int i = 0; i < lidar_sensors; ++i) {
    SimulatedSensor s;
    s.spec = {"lidar" + std::to_string(i), SensorType::kLidar3d, "lidar" + std::to_string(i)};
    s.reference_from_sensor = makePose(Eigen::Vector3d(-0.2 + 0.15 * i, 0.3 - 0.6 * i, 1.2 + 0.05 * i),
                                       rotationFromRollPitchYaw(0.03 - 0.02 * i, 0.04 * i, 0.5 - 0.8 * i));
    sensors.push_back(s);
  }
  for (int i = 0; i < laser_sensors; ++i) {
    SimulatedSensor s;
    s.spec = {"laser" + std::to_string(i), SensorType::kLaser2d, "laser" + std::to_string(i)};
    s.reference_from_sensor = makePose(Eigen::Vector3d(0.25, -0.1 + 0.2 * i, 0.95 + 0.1 * i),
                                       rotationFromRollPitchYaw(0.06 - 0.04 * i, 0.03 + 0.02 * i, -0.1 + 0.2 * i));
    sensors.push_back(s);
  }
  for (int i = 0; i < cameras; ++i) {
    SimulatedSensor s;
    s.spec = {"camera" + std::to_string(i), SensorType::kCamera, "camera" + std::to_string(i) + "_optical_frame"};
    s.reference_from_sensor = makePose(Eigen::Vector3d(0.05, 0.15 - 0.3 * i, 1.1 - 0.05 * i),
                                       rotationFromRollPitchYaw(-0.03 + 0.05 * i, 0.06 - 0.04 * i, 0.12 - 0.25 * i) *
                                           bodyFromOpticalRotation());
    sensors.push_back(s);
  }
  return sensors;
}

void pointLidarsAhead(std::vector<SimulatedSensor>* sensors) {
  int i = 0;
  for (SimulatedSensor& s : *sensors) {
    if (s.spec.type != SensorType::kLidar3d) continue;
    s.reference_from_sensor.linear() = rotationFromRollPitchYaw(0.03 - 0.02 * i, 0.05, 0.08 - 0.16 * i);
    ++i;
  }
}

Eigen::Matrix3d targetFacingRig() {
  // The target's z axis along -x of the reference frame.
  Eigen::Matrix3d facing;
  facing << 0, 0, -1,  //
      1, 0, 0,         //
      0, -1, 0;
  return facing;
}

TargetObservation observeTarget(const SimulatedSensor& sensor, const Eigen::Isometry3d& reference_from_target,
                                double half_width, double half_height, const RigSimulationOptions& options,
                                std::mt19937* rng) {
  TargetObservation observation;
  const Eigen::Isometry3d sensor_from_target = sensor.reference_from_sensor.inverse() * reference_from_target;
  std::vector<Eigen::Vector3d>& points = observation.points;
  if (sensor.spec.type == SensorType::kCamera) {
    // Corners projected with pixel noise; the whole pattern must be in view.
    const PinholeCamera camera = defaultKinectCamera();
    std::normal_distribution<double> pixel_noise(0.0, options.pixel_noise);
    std::vector<Eigen::Vector2d> corners;
    for (const Eigen::Vector3d& corner : options.pattern.corners()) {
      const Eigen::Vector3d p = sensor_from_target * corner;
      const Eigen::Vector2d uv = camera.project(p);
      if (!(p.z() > 0.3 && camera.contains(uv.x(), uv.y()))) return observation;
      corners.push_back(uv + (options.pixel_noise > 0.0 ? Eigen::Vector2d(pixel_noise(*rng), pixel_noise(*rng))
                                                        : Eigen::Vector2d::Zero()));
    }
    PatternObservation seen = observePattern(corners, options.pattern, camera, sensor.spec.name.c_str());
    observation.points = std::move(seen.points);
    observation.plane_measurements.push_back(seen.plane);
    return observation;
  }
  std::normal_distribution<double> range_noise(0.0, options.range_noise);
  const Eigen::Isometry3d target_from_sensor = sensor_from_target.inverse();
  const Eigen::Vector3d normal = sensor_from_target.linear().col(2);
  const double offset = -normal.dot(sensor_from_target.translation());
  for (const Eigen::Vector3d& ray : sensorRays(sensor.spec.type)) {
    const double denominator = normal.dot(ray);
    if (std::abs(denominator) < 1e-9) continue;
    const double range = -offset / denominator;
    if (range <= 0.3 || range > 8.0) continue;
    const Eigen::Vector3d on_target = target_from_sensor * (range * ray);
    if (std::abs(on_target.x()) > half_width || std::abs(on_target.y()) > half_height) continue;
    const double noise = options.range_noise > 0.0 ? range_noise(*rng) : 0.0;
    points.push_back((range + noise) * ray);
  }
  const std::size_t minimum = sensor.spec.type == SensorType::kLaser2d ? 10 : 30;
  if (points.size() < minimum) {
    points.clear();
    return observation;
  }
  // The edges as extraction finds them: each line's ends on the plane fitted to the noisy points.
  if (sensor.spec.type == SensorType::kLaser2d) {
    const Eigen::Vector3d along = (points.back() - points.front()).normalized();
    const Eigen::Vector3d across(-along.y(), along.x(), 0.0);
    observation.outline = boardOutlinePoints(points, Plane{across, -across.dot(centroidOf(points))}, {0.25 * M_PI / 180.0, 0.0});
  } else {
    const ScanSpacing spacing = sensor.spec.type == SensorType::kRgbd
                                    ? ScanSpacing{8.0 / 525.0, 8.0 / 525.0, ScanPattern::kPinhole}
                                    : ScanSpacing{0.2 * M_PI / 180.0, 2.0 * M_PI / 180.0, ScanPattern::kSpinning};
    observation.outline = boardOutlinePoints(points, fitPlane(points, sensor.spec.name.c_str()).plane, spacing);
  }
  return observation;
}

SimulatedRig simulateRig(const std::vector<SimulatedSensor>& sensors, const RigSimulationOptions& options) {
  if (options.target_poses < 1) {
    throw InputError("rig simulation: target_poses must be at least 1, got " + std::to_string(options.target_poses));
  }
  SimulatedRig rig;
  rig.sensors = sensors;
  std::mt19937 rng(options.seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const Eigen::Matrix3d facing = targetFacingRig();
  for (int k = 0; k < options.target_poses; ++k) {
    const double turn = options.turn_range >= 0.0 ? options.turn_range : options.tilt_range;
    const double yaw = options.parallel_targets ? 0.0 : turn * unit(rng);
    const double pitch = options.parallel_targets ? 0.0 : options.tilt_range * unit(rng);
    const Eigen::Vector3d position(options.target_distance + 0.3 * unit(rng), 0.4 * unit(rng), 1.0 + 0.2 * unit(rng));
    rig.reference_from_target.push_back(makePose(position, rotationFromRollPitchYaw(0.0, pitch, yaw) * facing));
  }
  for (std::size_t s = 0; s < sensors.size(); ++s) {
    const SensorType type = sensors[s].spec.type;
    for (int k = 0; k < options.target_poses; ++k) {
      // An outlier sees another surface (a large panel elsewhere in front of the rig) or is associated
      // with the wrong target pose (it saw the target at another pose).
      const bool outlier = type != SensorType::kLaser2d && type != SensorType::kCamera && uniform(rng) < options.outlier_fraction;
      const bool wrong_pose = outlier && options.target_poses > 1 && uniform(rng) < 0.5;
      Eigen::Isometry3d seen = rig.reference_from_target[k];
      if (wrong_pose) {
        seen = rig.reference_from_target[(k + 1 + static_cast<int>(uniform(rng) * (options.target_poses - 1))) % options.target_poses];
      } else if (outlier) {
        seen = makePose(Eigen::Vector3d(2.5 + unit(rng), unit(rng), 1.0 + 0.3 * unit(rng)),
                        rotationFromRollPitchYaw(0.0, 0.8 * unit(rng), 0.8 * unit(rng)) * facing);
      }
      const double scale = outlier && !wrong_pose ? 2.0 : 1.0;
      TargetObservation observation = observeTarget(sensors[s], seen, scale * 0.5 * options.target_width,
                                                    scale * 0.5 * options.target_height, options, &rng);
      observation.sensor = static_cast<int>(s);
      observation.target_pose = k;
      if (observation.points.empty()) continue;
      rig.observations.push_back(std::move(observation));
      rig.is_outlier.push_back(outlier);
    }
  }
  return rig;
}

}  // namespace vocal
