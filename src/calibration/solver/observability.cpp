#include "vocal/calibration/solver/observability.h"

#include <sstream>

#include <Eigen/SVD>

namespace vocal {

namespace {
std::string direction(const Eigen::Vector3d& v) {
  std::ostringstream text;
  text.precision(2);
  text << std::fixed << "[" << v.x() << " " << v.y() << " " << v.z() << "]";
  return text.str();
}

void check(const std::string& who, const std::vector<Eigen::Vector3d>& normals, double weak_spread,
           std::vector<ObservabilityWarning>* warnings) {
  if (normals.size() < 3) {
    warnings->push_back({who, "all", 0.0,
                         who + ": " + std::to_string(normals.size()) + " target poses, at least 3 non-parallel are needed"});
    return;
  }
  Eigen::MatrixXd stacked(normals.size(), 3);
  for (std::size_t i = 0; i < normals.size(); ++i) stacked.row(i) = normals[i].transpose();
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(stacked, Eigen::ComputeFullV);
  const Eigen::Vector3d s = svd.singularValues();
  const double spread = s[2] / s[0];
  if (spread < weak_spread) {
    const std::string dof = "translation along " + direction(svd.matrixV().col(2));
    std::ostringstream message;
    message.precision(3);
    message << who << ": " << dof << " is weakly constrained (normal spread " << spread << " < " << weak_spread
            << "): tilt the target further between poses";
    warnings->push_back({who, dof, spread, message.str()});
  }
  if (s[1] / s[0] < weak_spread) {
    // Every normal is close to one direction: rotation about it is free too.
    const std::string dof = "rotation about " + direction(svd.matrixV().col(0));
    warnings->push_back({who, dof, s[1] / s[0], who + ": " + dof + " is unconstrained: every target pose had nearly the same orientation"});
  }
}
}  // namespace

std::vector<ObservabilityWarning> checkObservability(const std::vector<SensorSpec>& sensors,
                                                     const std::vector<std::map<int, Plane>>& planes, double weak_spread) {
  std::vector<ObservabilityWarning> warnings;
  for (std::size_t a = 0; a < sensors.size(); ++a) {
    if (sensors[a].type == SensorType::kLaser2d) continue;
    std::vector<Eigen::Vector3d> own;
    for (const auto& entry : planes[a]) own.push_back(entry.second.normal);
    check("sensor '" + sensors[a].name + "'", own, weak_spread, &warnings);
    for (std::size_t b = a + 1; b < sensors.size(); ++b) {
      if (sensors[b].type == SensorType::kLaser2d) continue;
      std::vector<Eigen::Vector3d> shared;
      for (const auto& entry : planes[a])
        if (planes[b].count(entry.first)) shared.push_back(entry.second.normal);
      if (shared.empty()) continue;  // the spanning tree reports disconnected sensors
      check("pair '" + sensors[a].name + "' + '" + sensors[b].name + "'", shared, weak_spread, &warnings);
    }
  }
  return warnings;
}

}  // namespace vocal
