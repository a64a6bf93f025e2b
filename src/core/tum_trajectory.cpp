#include "vocal/core/tum_trajectory.h"

#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <limits>
#include <memory>

#include "vocal/core/errors.h"
#include "vocal/core/se3.h"
#include "vocal/core/tum_text_file.h"

namespace vocal {

Trajectory readTumTrajectory(const std::string& path) {
  Trajectory trajectory;
  double previous_stamp = -std::numeric_limits<double>::infinity();
  for (const TumTextLine& line : readTumTextLines(path)) {
    if (line.fields.size() != 8) {
      throw InputError(tumLineError(path, line.line_number,
                                    "expected 8 fields 'timestamp tx ty tz qx qy qz qw', found " +
                                        std::to_string(line.fields.size())));
    }
    static const char* const kNames[] = {"timestamp", "tx", "ty", "tz", "qx", "qy", "qz", "qw"};
    double v[8];
    for (std::size_t i = 0; i < 8; ++i) {
      v[i] = parseTumNumber(path, line, i, kNames[i]);
    }
    requireIncreasingStamp(path, line, previous_stamp, v[0]);
    previous_stamp = v[0];
    const Eigen::Quaterniond q(v[7], v[4], v[5], v[6]);
    // TUM files carry 4 decimals; anything farther from unit length is not a rotation.
    if (std::abs(q.norm() - 1.0) > 1e-3) {
      throw InputError(tumLineError(path, line.line_number,
                                    "quaternion has norm " + std::to_string(q.norm()) + ", expected 1"));
    }
    trajectory.push_back({v[0], poseFromTranslationQuaternion({v[1], v[2], v[3]}, q)});
  }
  return trajectory;
}

void writeTumTrajectory(const std::string& path, const Trajectory& trajectory) {
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> file(std::fopen(path.c_str(), "w"), &std::fclose);
  if (!file) {
    throw InputError(path + ": cannot write trajectory (" + std::strerror(errno) + ")");
  }
  std::fprintf(file.get(), "# timestamp tx ty tz qx qy qz qw\n");
  for (const StampedPose& p : trajectory) {
    const Eigen::Vector3d t = p.pose.translation();
    const Eigen::Quaterniond q(p.pose.rotation());
    // %.17g round-trips doubles exactly; the stamp keeps TUM's fixed-point look.
    std::fprintf(file.get(), "%.6f %.17g %.17g %.17g %.17g %.17g %.17g %.17g\n", p.stamp, t.x(), t.y(), t.z(),
                 q.x(), q.y(), q.z(), q.w());
  }
  if (std::ferror(file.get())) {
    throw InputError(path + ": write error");
  }
}

std::vector<double> trajectoryStamps(const Trajectory& trajectory) {
  std::vector<double> stamps;
  stamps.reserve(trajectory.size());
  for (const StampedPose& p : trajectory) {
    stamps.push_back(p.stamp);
  }
  return stamps;
}

}  // namespace vocal
