#include "vocal/core/gravity.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <limits>
#include <sstream>

#include <Eigen/Geometry>

#include "vocal/core/errors.h"
#include "vocal/core/tum_text_file.h"

namespace vocal {

std::vector<AccelerometerSample> readAccelerometerFile(const std::string& path) {
  std::vector<AccelerometerSample> samples;
  double previous_stamp = -std::numeric_limits<double>::infinity();
  for (const TumTextLine& line : readTumTextLines(path)) {
    if (line.fields.size() != 4) {
      throw InputError(tumLineError(path, line.line_number,
                                    "expected 4 fields 'timestamp ax ay az', found " + std::to_string(line.fields.size())));
    }
    AccelerometerSample s;
    s.stamp = parseTumNumber(path, line, 0, "timestamp");
    requireIncreasingStamp(path, line, previous_stamp, s.stamp);
    previous_stamp = s.stamp;
    s.specific_force = Eigen::Vector3d(parseTumNumber(path, line, 1, "ax"), parseTumNumber(path, line, 2, "ay"),
                                       parseTumNumber(path, line, 3, "az"));
    samples.push_back(s);
  }
  return samples;
}

void writeAccelerometerFile(const std::string& path, const std::vector<AccelerometerSample>& samples) {
  std::ofstream out(path);
  if (!out) throw InputError(path + ": cannot write the accelerometer file");
  out << "# accelerometer data\n# timestamp ax ay az\n";
  char line[128];
  for (const AccelerometerSample& s : samples) {
    std::snprintf(line, sizeof(line), "%.6f %.6f %.6f %.6f\n", s.stamp, s.specific_force.x(), s.specific_force.y(),
                  s.specific_force.z());
    out << line;
  }
}

Eigen::Matrix3d opticalFromKinectAccelerometer() { return Eigen::Vector3d(-1.0, -1.0, 1.0).asDiagonal(); }

Eigen::Matrix3d levelFromUp(const Eigen::Vector3d& up) {
  return Eigen::Quaterniond::FromTwoVectors(up.normalized(), Eigen::Vector3d::UnitZ()).toRotationMatrix();
}

std::optional<Eigen::Vector3d> stillSpecificForce(const std::vector<AccelerometerSample>& samples, double stamp, double window,
                                                  std::string* why) {
  auto fail = [&](const std::string& reason) {
    if (why) *why = reason;
    return std::nullopt;
  };
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  int count = 0;
  for (const AccelerometerSample& s : samples) {
    if (std::fabs(s.stamp - stamp) > window) continue;
    sum += s.specific_force;
    ++count;
  }
  if (count == 0) {
    std::ostringstream reason;
    reason << "no accelerometer sample within " << window << " s of the first frame";
    return fail(reason.str());
  }
  const Eigen::Vector3d mean = sum / count;
  if (std::fabs(mean.norm() - kStandardGravity) > 0.1 * kStandardGravity) {
    std::ostringstream reason;
    reason << "the accelerometer read " << mean.norm() << " m/s^2 on average, not gravity's " << kStandardGravity
           << " (moving, or not in m/s^2)";
    return fail(reason.str());
  }
  return mean;
}

}  // namespace vocal
