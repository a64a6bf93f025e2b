#include "vocal/calibration/point_statistics.h"

#include <algorithm>

#include <Eigen/Eigenvalues>

namespace vocal {

double median(std::vector<double> values) {
  if (values.empty()) return 0.0;
  std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
  return values[values.size() / 2];
}

Eigen::Vector3d centroidOf(const std::vector<Eigen::Vector3d>& points) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& p : points) sum += p;
  return points.empty() ? sum : Eigen::Vector3d(sum / static_cast<double>(points.size()));
}

PrincipalAxes principalAxesOf(const std::vector<Eigen::Vector3d>& points) {
  PrincipalAxes result;
  result.centroid = centroidOf(points);
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (const Eigen::Vector3d& p : points) scatter += (p - result.centroid) * (p - result.centroid).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(scatter);  // eigenvalues ascending
  for (int k = 0; k < 3; ++k) {
    result.axes.col(k) = eigen.eigenvectors().col(2 - k);
    result.spread[k] = eigen.eigenvalues()[2 - k];
  }
  return result;
}

}  // namespace vocal
