#pragma once
// What MSG-Cal works on: the sensors of a rig and their observations of the planar target.

#include <string>
#include <vector>

#include <Eigen/Geometry>

namespace vocal {

enum class SensorType { kCamera, kRgbd, kLidar3d, kLaser2d };

SensorType parseSensorType(const std::string& name);  // camera, rgbd, lidar3d, laser2d
std::string sensorTypeName(SensorType type);

struct SensorSpec {
  std::string name;
  SensorType type = SensorType::kRgbd;
  std::string frame_id;
};

// One sensor's view of the target while it was held at one pose: points on the target in the sensor
// frame (a depth or lidar sensor's inliers, a camera's pattern corners from its pose estimate).
struct TargetObservation {
  int sensor = 0;       // index into the sensor list
  int target_pose = 0;  // which still period of the target (association result)
  std::vector<Eigen::Vector3d> points;
  // Standard deviation of one point's distance to the target plane, metres, in the sense of the
  // graph's weighting; 0 = estimate it from the points' own fit (range sensors). A camera sets it
  // from its pose covariance (its corners share one plane error).
  double point_sigma = 0.0;
};

}  // namespace vocal
