#pragma once
// A simulated rig with ground-truth extrinsics observing a planar target moved through M poses: the
// test data of the calibration. Depth and lidar sensors see points of the target rectangle inside their
// field of view (a lidar's limited to its rings, a 2D laser's to its scan plane) with range noise along
// each ray.

#include <cstdint>
#include <vector>

#include "vocal/calibration/calibration_types.h"

namespace vocal {

struct SimulatedSensor {
  SensorSpec spec;
  Eigen::Isometry3d reference_from_sensor = Eigen::Isometry3d::Identity();
};

struct RigSimulationOptions {
  int target_poses = 30;
  double target_width = 0.9;   // metres
  double target_height = 0.7;
  double range_noise = 0.0;    // metres, standard deviation along each ray
  double tilt_range = 0.6;     // radians: target normals spread up to this from facing the rig
  bool parallel_targets = false;  // every pose keeps the same orientation (a degenerate data set)
  // Fraction of plane-sensor observations replaced by points of another surface (a wall, a wrong
  // association) under the same target pose id.
  double outlier_fraction = 0.0;
  std::uint32_t seed = 1;
};

struct SimulatedRig {
  std::vector<SimulatedSensor> sensors;
  std::vector<Eigen::Isometry3d> reference_from_target;  // ground truth per target pose
  std::vector<TargetObservation> observations;
  std::vector<bool> is_outlier;  // per observation
};

// A rig of RGB-D sensors (the first at the reference), 16-ring lidars and 2D lasers (270 degrees,
// 0.25 degree steps), each looking roughly forward (+x).
std::vector<SimulatedSensor> exampleRig(int rgbd_sensors, int lidar_sensors, int laser_sensors = 0);

// Throws InputError for an unsupported sensor type (cameras are not simulated yet) or fewer than 1
// target pose.
SimulatedRig simulateRig(const std::vector<SimulatedSensor>& sensors, const RigSimulationOptions& options);

}  // namespace vocal
