#include "vocal/calibration/calibration_types.h"

#include <cmath>

#include "vocal/core/errors.h"

namespace vocal {

SensorType parseSensorType(const std::string& name) {
  if (name == "camera") return SensorType::kCamera;
  if (name == "rgbd") return SensorType::kRgbd;
  if (name == "lidar3d") return SensorType::kLidar3d;
  if (name == "laser2d") return SensorType::kLaser2d;
  throw InputError("sensor type '" + name + "' is unknown: expected camera, rgbd, lidar3d, laser2d or imu");
}

std::string sensorTypeName(SensorType type) {
  switch (type) {
    case SensorType::kCamera: return "camera";
    case SensorType::kRgbd: return "rgbd";
    case SensorType::kLidar3d: return "lidar3d";
    case SensorType::kLaser2d: return "laser2d";
  }
  return "unknown";
}

PlaneMeasurement turnedHalfway(const PlaneMeasurement& view) {
  PlaneMeasurement turned = view;
  const Eigen::Matrix3d half_turn = Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  turned.sensor_from_pattern.linear() = view.sensor_from_pattern.linear() * half_turn;
  Eigen::Matrix<double, 6, 6> change = Eigen::Matrix<double, 6, 6>::Identity();
  change.topLeftCorner<3, 3>() = half_turn.transpose();
  turned.pose_covariance = change * view.pose_covariance * change.transpose();
  turned.pose_per_intrinsics = change * view.pose_per_intrinsics;
  // The plane's tilts along the pattern's x and y change sign, its distance does not.
  const Eigen::Matrix3d tilts = Eigen::Vector3d(-1.0, -1.0, 1.0).asDiagonal();
  turned.covariance = tilts * view.covariance * tilts;
  return turned;
}

}  // namespace vocal
