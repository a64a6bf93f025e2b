#include "vocal/calibration/calibration_types.h"

#include "vocal/core/errors.h"

namespace vocal {

SensorType parseSensorType(const std::string& name) {
  if (name == "camera") return SensorType::kCamera;
  if (name == "rgbd") return SensorType::kRgbd;
  if (name == "lidar3d") return SensorType::kLidar3d;
  if (name == "laser2d") return SensorType::kLaser2d;
  throw InputError("sensor type '" + name + "' is unknown: expected camera, rgbd, lidar3d or laser2d");
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

}  // namespace vocal
