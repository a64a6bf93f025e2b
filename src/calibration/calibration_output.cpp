#include "vocal/calibration/calibration_output.h"

#include <cmath>
#include <fstream>
#include <iomanip>

#include "vocal/core/errors.h"

namespace vocal {

namespace {
std::ofstream openOutput(const std::string& path) {
  std::ofstream file(path);
  if (!file) throw InputError(path + ": cannot write calibration output");
  file << std::setprecision(9);
  return file;
}

void finish(std::ofstream& file, const std::string& path) {
  if (!file.flush()) throw InputError(path + ": write error");
}

void checkSizes(const std::vector<SensorSpec>& sensors, const CalibrationResult& result) {
  if (sensors.size() != result.sensors.size()) {
    throw InputError("calibration output: " + std::to_string(sensors.size()) + " sensors but " +
                     std::to_string(result.sensors.size()) + " results");
  }
}
}  // namespace

void writeCalibrationYaml(const std::string& path, const std::string& reference_frame,
                          const std::vector<SensorSpec>& sensors, const CalibrationResult& result, const PoseJackknife* spread,
                          const std::vector<std::optional<RingOffsets>>* ring_offsets) {
  checkSizes(sensors, result);
  std::ofstream file = openOutput(path);
  file << "# vocal MSG-Cal result: pose of each sensor frame in " << reference_frame << "\n"
       << "reference_frame: " << reference_frame << "\n"
       << "rms_m: " << result.rms << "\n"
       << "sensors:\n";
  for (std::size_t s = 0; s < sensors.size(); ++s) {
    const SensorCalibration& c = result.sensors[s];
    const Eigen::Vector3d t = c.reference_from_sensor.translation();
    const Eigen::Quaterniond q(c.reference_from_sensor.rotation());
    const Vector6d& sd = c.standard_deviation;
    file << "  - name: " << sensors[s].name << "\n"
         << "    type: " << sensorTypeName(sensors[s].type) << "\n"
         << "    frame_id: " << sensors[s].frame_id << "\n"
         << "    parent: " << reference_frame << "\n"
         << "    translation: [" << t.x() << ", " << t.y() << ", " << t.z() << "]\n"
         << "    rotation: [" << q.x() << ", " << q.y() << ", " << q.z() << ", " << q.w() << "]\n"
         << "    translation_stddev: [" << sd[0] << ", " << sd[1] << ", " << sd[2] << "]\n"
         << "    rotation_stddev: [" << sd[3] << ", " << sd[4] << ", " << sd[5] << "]  # rad, about x y z\n";
    if (spread && s < spread->standard_deviation.size()) {
      const Vector6d& jk = spread->standard_deviation[s];
      file << "    translation_spread: [" << jk[0] << ", " << jk[1] << ", " << jk[2] << "]  # m, jackknife over still poses\n"
           << "    rotation_spread: [" << jk[3] << ", " << jk[4] << ", " << jk[5] << "]  # rad, jackknife over still poses\n";
    }
    if (ring_offsets && s < ring_offsets->size() && (*ring_offsets)[s]) {
      const RingOffsets& rings = *(*ring_offsets)[s];
      const auto list = [&](const char* key, auto value, const char* comment) {
        file << "      " << key << ": [";
        for (std::size_t r = 0; r < rings.elevations.size(); ++r) file << (r ? ", " : "") << value(r);
        file << "]" << comment << "\n";
      };
      file << "    ring_offsets:  # from " << rings.planes << " room planes; the board's returns were moved back along their rays by them\n";
      list("elevation_deg", [&](std::size_t r) { return rings.elevations[r] * 180.0 / M_PI; }, "");
      list("offset_m", [&](std::size_t r) { return rings.offsets[r]; }, "  # how much too long each ring's ranges read");
      list("offset_stddev_m", [&](std::size_t r) { return rings.sigmas[r]; }, "");
    }
    file << "    rms_m: " << c.rms << "\n"
         << "    observations: " << c.observations << "\n";
  }
  finish(file, path);
}

void writeUrdfSnippet(const std::string& path, const std::string& reference_frame, const std::vector<SensorSpec>& sensors,
                      const CalibrationResult& result) {
  checkSizes(sensors, result);
  std::ofstream file = openOutput(path);
  file << "<!-- vocal MSG-Cal result: paste into the robot's URDF -->\n";
  for (std::size_t s = 0; s < sensors.size(); ++s) {
    const Eigen::Isometry3d& pose = result.sensors[s].reference_from_sensor;
    // URDF rpy: fixed axes, R = Rz(yaw) Ry(pitch) Rx(roll).
    const Eigen::Vector3d ypr = pose.rotation().eulerAngles(2, 1, 0);
    const Eigen::Vector3d t = pose.translation();
    file << "<link name=\"" << sensors[s].frame_id << "\"/>\n"
         << "<joint name=\"" << reference_frame << "_to_" << sensors[s].frame_id << "\" type=\"fixed\">\n"
         << "  <parent link=\"" << reference_frame << "\"/>\n"
         << "  <child link=\"" << sensors[s].frame_id << "\"/>\n"
         << "  <origin xyz=\"" << t.x() << " " << t.y() << " " << t.z() << "\" rpy=\"" << ypr[2] << " " << ypr[1] << " "
         << ypr[0] << "\"/>\n"
         << "</joint>\n";
  }
  finish(file, path);
}

void writeStaticTransformLaunch(const std::string& path, const std::string& reference_frame,
                                const std::vector<SensorSpec>& sensors, const CalibrationResult& result) {
  checkSizes(sensors, result);
  std::ofstream file = openOutput(path);
  file << "<launch>\n  <!-- vocal MSG-Cal result as static transforms -->\n";
  for (std::size_t s = 0; s < sensors.size(); ++s) {
    const Eigen::Isometry3d& pose = result.sensors[s].reference_from_sensor;
    const Eigen::Vector3d t = pose.translation();
    const Eigen::Quaterniond q(pose.rotation());
    file << "  <node pkg=\"tf2_ros\" type=\"static_transform_publisher\" name=\"" << sensors[s].name
         << "_extrinsic\" args=\"" << t.x() << " " << t.y() << " " << t.z() << " " << q.x() << " " << q.y() << " "
         << q.z() << " " << q.w() << " " << reference_frame << " " << sensors[s].frame_id << "\"/>\n";
  }
  file << "</launch>\n";
  finish(file, path);
}

}  // namespace vocal
