#include "vocal/core/imu_samples.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>

#include "vocal/core/errors.h"
#include "vocal/core/tum_text_file.h"
#include "vocal/core/yaml_file.h"

namespace vocal {

std::vector<ImuSample> readImuFile(const std::string& path) {
  std::vector<ImuSample> samples;
  double previous_stamp = -std::numeric_limits<double>::infinity();
  for (const TumTextLine& line : readTumTextLines(path)) {
    if (line.fields.size() != 7) {
      throw InputError(tumLineError(path, line.line_number,
                                    "expected 7 fields 'timestamp wx wy wz ax ay az', found " + std::to_string(line.fields.size())));
    }
    ImuSample s;
    s.stamp = parseTumNumber(path, line, 0, "timestamp");
    requireIncreasingStamp(path, line, previous_stamp, s.stamp);
    previous_stamp = s.stamp;
    s.angular_velocity = {parseTumNumber(path, line, 1, "wx"), parseTumNumber(path, line, 2, "wy"), parseTumNumber(path, line, 3, "wz")};
    s.linear_acceleration = {parseTumNumber(path, line, 4, "ax"), parseTumNumber(path, line, 5, "ay"), parseTumNumber(path, line, 6, "az")};
    samples.push_back(s);
  }
  return samples;
}

void writeImuFile(const std::string& path, const std::vector<ImuSample>& samples) {
  std::ofstream out(path);
  if (!out) throw InputError(path + ": cannot write the IMU file");
  out << "# imu data\n# timestamp wx wy wz ax ay az (s, rad/s, m/s^2, IMU frame)\n";
  char line[256];
  for (const ImuSample& s : samples) {
    std::snprintf(line, sizeof(line), "%.6f %.9f %.9f %.9f %.6f %.6f %.6f\n", s.stamp, s.angular_velocity.x(), s.angular_velocity.y(),
                  s.angular_velocity.z(), s.linear_acceleration.x(), s.linear_acceleration.y(), s.linear_acceleration.z());
    out << line;
  }
}

namespace {
std::vector<double> numbers(const YAML::Node& node, std::size_t count, const std::string& where) {
  if (!node || !node.IsSequence() || node.size() != count) {
    throw InputError(where + ": expected a list of " + std::to_string(count) + " numbers");
  }
  std::vector<double> out;
  for (const YAML::Node& value : node) {
    double v = 0.0;
    try {
      v = value.as<double>();
    } catch (const YAML::Exception&) {
      throw InputError(where + ": '" + value.as<std::string>("") + "' is not a number");
    }
    if (!std::isfinite(v)) throw InputError(where + ": not finite");
    out.push_back(v);
  }
  return out;
}

double nonNegative(const YAML::Node& parent, const char* key, double fallback, const std::string& where) {
  const YAML::Node node = parent[key];
  if (!node) return fallback;
  double v = 0.0;
  try {
    v = node.as<double>();
  } catch (const YAML::Exception&) {
    throw InputError(where + "." + key + ": not a number");
  }
  if (!(v >= 0.0) || !std::isfinite(v)) throw InputError(where + "." + key + ": must be a finite number >= 0");
  return v;
}
}  // namespace

ImuExtrinsics readImuExtrinsics(const std::string& path) {
  const YAML::Node root = loadYamlFile(path, "the IMU extrinsics");
  ImuExtrinsics e;
  if (root["imu_frame"]) e.imu_frame = root["imu_frame"].as<std::string>();
  if (root["camera_frame"]) e.camera_frame = root["camera_frame"].as<std::string>();
  const YAML::Node pose = root["camera_in_imu"];
  if (!pose || !pose.IsMap()) throw InputError(path + ": camera_in_imu: missing (translation: [x, y, z], rotation: [qx, qy, qz, qw])");
  const std::vector<double> t = numbers(pose["translation"], 3, path + ": camera_in_imu.translation");
  const std::vector<double> q = numbers(pose["rotation"], 4, path + ": camera_in_imu.rotation");
  const Eigen::Quaterniond rotation(q[3], q[0], q[1], q[2]);
  if (std::fabs(rotation.norm() - 1.0) > 1e-3) {
    throw InputError(path + ": camera_in_imu.rotation: not a unit quaternion [qx, qy, qz, qw] (norm " + std::to_string(rotation.norm()) + ")");
  }
  e.camera_in_imu.linear() = rotation.normalized().toRotationMatrix();
  e.camera_in_imu.translation() = Eigen::Vector3d(t[0], t[1], t[2]);
  if (root["time_offset"]) {
    try {
      e.time_offset = root["time_offset"].as<double>();
    } catch (const YAML::Exception&) {
      throw InputError(path + ": time_offset: not a number (seconds)");
    }
    if (!std::isfinite(e.time_offset)) throw InputError(path + ": time_offset: not finite");
  }
  if (const YAML::Node noise = root["noise"]) {
    const std::string where = path + ": noise";
    e.noise.gyro_noise_density = nonNegative(noise, "gyro_noise_density", e.noise.gyro_noise_density, where);
    e.noise.gyro_bias_random_walk = nonNegative(noise, "gyro_bias_random_walk", e.noise.gyro_bias_random_walk, where);
    e.noise.accel_noise_density = nonNegative(noise, "accel_noise_density", e.noise.accel_noise_density, where);
    e.noise.accel_bias_random_walk = nonNegative(noise, "accel_bias_random_walk", e.noise.accel_bias_random_walk, where);
  }
  return e;
}

void writeImuExtrinsics(const std::string& path, const ImuExtrinsics& e) {
  std::ofstream out(path);
  if (!out) throw InputError(path + ": cannot write the IMU extrinsics");
  const Eigen::Quaterniond q(e.camera_in_imu.rotation());
  const Eigen::Vector3d& t = e.camera_in_imu.translation();
  char text[1024];
  std::snprintf(text, sizeof(text),
                "imu_frame: %s\ncamera_frame: %s\n"
                "camera_in_imu: {translation: [%.6f, %.6f, %.6f], rotation: [%.9f, %.9f, %.9f, %.9f]}  # the optical frame in the IMU frame\n"
                "time_offset: %.6f  # seconds: IMU stamp = camera stamp + offset\n"
                "noise: {gyro_noise_density: %g, gyro_bias_random_walk: %g, accel_noise_density: %g, accel_bias_random_walk: %g}\n",
                e.imu_frame.c_str(), e.camera_frame.c_str(), t.x(), t.y(), t.z(), q.x(), q.y(), q.z(), q.w(), e.time_offset,
                e.noise.gyro_noise_density, e.noise.gyro_bias_random_walk, e.noise.accel_noise_density, e.noise.accel_bias_random_walk);
  out << text;
}

double imuRate(const std::vector<ImuSample>& samples) {
  if (samples.size() < 2) return 0.0;
  const double span = samples.back().stamp - samples.front().stamp;
  return span > 0.0 ? (samples.size() - 1) / span : 0.0;
}

}  // namespace vocal
