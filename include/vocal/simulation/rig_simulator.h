#pragma once
// A simulated rig with ground-truth extrinsics observing a planar target moved through M poses: the
// test data of the calibration. Depth and lidar sensors see points of the target rectangle inside their
// field of view (a lidar's limited to its rings, a 2D laser's to its scan plane) with range noise along
// each ray; cameras see the pattern's corners with pixel noise and estimate its pose (PnP).

#include <cstdint>
#include <random>
#include <vector>

#include "vocal/calibration/calibration_types.h"
#include "vocal/calibration/extraction/pattern_observation.h"

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
  double pixel_noise = 0.0;    // camera corner noise, pixels (standard deviation per axis)
  double target_distance = 1.6;  // metres ahead of the rig (x), +-0.3
  double tilt_range = 0.6;     // radians: target normals spread up to this from facing the rig
  double turn_range = -1.0;    // radians turned left / right, when less than tilt_range (a board tilted
                               // mainly up and down: normals of little spread); < 0: tilt_range
  bool parallel_targets = false;  // every pose keeps the same orientation (a degenerate data set)
  // Fraction of depth and lidar observations that are outliers under their target pose id: half see
  // another surface (a large panel), half the target at another pose (a wrong association).
  double outlier_fraction = 0.0;
  std::uint32_t seed = 1;
  TargetPattern pattern;  // what cameras see (its corners must lie on the target rectangle)
};

struct SimulatedRig {
  std::vector<SimulatedSensor> sensors;
  std::vector<Eigen::Isometry3d> reference_from_target;  // ground truth per target pose
  std::vector<TargetObservation> observations;
  std::vector<bool> is_outlier;  // per observation
};

// A rig of RGB-D sensors (the first at the reference), 16-ring lidars, 2D lasers (270 degrees, 0.25
// degree steps) and cameras (640x480, ROS default intrinsics), each looking roughly forward (+x).
std::vector<SimulatedSensor> exampleRig(int rgbd_sensors, int lidar_sensors, int laser_sensors = 0, int cameras = 0);

// A forward-looking (solid-state) lidar's mounting: each lidar of `sensors` turned to look along the rig's
// +x, where the target poses are, with a small roll, pitch and yaw of its own; its place kept.
void pointLidarsAhead(std::vector<SimulatedSensor>* sensors);

// What one sensor sees of a target rectangle (half extents in metres) at the given pose: its points in
// the sensor frame (none when too little is in view) and where they end on the board's edges, or, for a
// camera, its plane measurement. The sensor and target_pose fields are left for the caller.
TargetObservation observeTarget(const SimulatedSensor& sensor, const Eigen::Isometry3d& reference_from_target,
                                double half_width, double half_height, const RigSimulationOptions& options,
                                std::mt19937* rng);

// The target orientation that faces the rig (its z axis along -x of the reference frame).
Eigen::Matrix3d targetFacingRig();

// Throws InputError for fewer than 1 target pose.
SimulatedRig simulateRig(const std::vector<SimulatedSensor>& sensors, const RigSimulationOptions& options);

}  // namespace vocal
