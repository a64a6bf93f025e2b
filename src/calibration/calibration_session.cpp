#include "vocal/calibration/calibration_session.h"

#include "vocal/calibration/pattern_observation.h"
#include "vocal/core/errors.h"

namespace vocal {

CalibrationSession::CalibrationSession(RigDescription rig, TargetExtractionOptions extraction, StillnessOptions stillness)
    : rig_(std::move(rig)), extraction_(extraction), stillness_(stillness), counts_(rig_.sensors.size()) {}

int CalibrationSession::sensorIndex(const std::string& name) const {
  for (std::size_t i = 0; i < rig_.sensors.size(); ++i)
    if (rig_.sensors[i].spec.name == name) return static_cast<int>(i);
  return -1;
}

const RigSensorDescription& CalibrationSession::checkSensor(int sensor, SensorType expected, const char* data) const {
  if (sensor < 0 || sensor >= static_cast<int>(rig_.sensors.size())) {
    throw InputError("calibration session: sensor index " + std::to_string(sensor) + " is not one of the " +
                     std::to_string(rig_.sensors.size()) + " sensors of the rig");
  }
  const RigSensorDescription& description = rig_.sensors[sensor];
  if (description.spec.type != expected) {
    throw InputError("sensor '" + description.spec.name + "' is a " + sensorTypeName(description.spec.type) + " sensor: it takes no " +
                     data);
  }
  return description;
}

bool CalibrationSession::record(int sensor, double stamp, std::vector<Eigen::Vector3d> points, std::vector<PlaneMeasurement> planes) {
  ++counts_[sensor].received;
  if (points.empty()) return false;
  ++counts_[sensor].target_found;
  TimedObservation observation;
  observation.sensor = sensor;
  observation.stamp = stamp;
  observation.points = std::move(points);
  observation.plane_measurements = std::move(planes);
  observations_.push_back(std::move(observation));
  return true;
}

bool CalibrationSession::addCloud(int sensor, double stamp, const std::vector<Eigen::Vector3d>& cloud) {
  checkSensor(sensor, SensorType::kLidar3d, "point cloud");
  return record(sensor, stamp, extractTargetPoints(cloud, rig_.target.width, rig_.target.height, extraction_), {});
}

bool CalibrationSession::addScan(int sensor, double stamp, const std::vector<Eigen::Vector3d>& scan) {
  checkSensor(sensor, SensorType::kLaser2d, "2D scan");
  return record(sensor, stamp, extractTargetSegment(scan, rig_.target.width, rig_.target.height, extraction_), {});
}

bool CalibrationSession::addDepth(int sensor, double stamp, const DepthImage& depth, const PinholeCamera& camera) {
  const RigSensorDescription& description = checkSensor(sensor, SensorType::kRgbd, "depth image");
  if (!depth.sameSize(camera.width, camera.height)) {
    throw InputError("sensor '" + description.spec.name + "': depth image is " + std::to_string(depth.width()) + "x" +
                     std::to_string(depth.height()) + " but its camera_info is " + std::to_string(camera.width) + "x" +
                     std::to_string(camera.height));
  }
  // Every second pixel: the plane fit gains nothing from more, extraction runs four times faster.
  std::vector<Eigen::Vector3d> cloud;
  for (int v = 0; v < depth.height(); v += 2)
    for (int u = 0; u < depth.width(); u += 2)
      if (isValidDepth(depth(u, v))) cloud.push_back(camera.backProject(u, v, depth(u, v)));
  return record(sensor, stamp, extractTargetPoints(cloud, rig_.target.width, rig_.target.height, extraction_), {});
}

bool CalibrationSession::addImage(int sensor, double stamp, const ColorImage& image, const PinholeCamera& camera,
                                  const LensDistortion& distortion) {
  const RigSensorDescription& description = checkSensor(sensor, SensorType::kCamera, "image");
  const char* name = description.spec.name.c_str();
  std::vector<Eigen::Vector2d> corners;
  try {
    corners = detectPattern(image, rig_.target.pattern, name);
  } catch (const InputError&) {
    return record(sensor, stamp, {}, {});  // no board in view: normal while the target moves
  }
  PatternObservation seen = observePattern(corners, rig_.target.pattern, camera, name, distortion);
  return record(sensor, stamp, std::move(seen.points), {seen.plane});
}

std::vector<TargetObservation> CalibrationSession::associatedObservations() const {
  return associateStillTarget(rig_.specs(), observations_, stillness_);
}

CalibrationResult CalibrationSession::calibrate(CalibrationOptions options) const {
  return calibrate(associatedObservations(), options);
}

CalibrationResult CalibrationSession::calibrate(const std::vector<TargetObservation>& associated,
                                                CalibrationOptions options) const {
  options.reference_sensor = rig_.reference_sensor;
  options.reference_pose = *rig_.sensors[rig_.reference_sensor].pose;
  // A sensor that saw the target but was never still with it: say why, rather than "never sees the target".
  const std::string unassociated = missingStillnessExplanation(rig_.specs(), observations_, associated, stillness_);
  if (!unassociated.empty()) throw InputError("calibration: " + unassociated);
  return calibrateRig(rig_.specs(), associated, options);
}

}  // namespace vocal
