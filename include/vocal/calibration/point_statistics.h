#pragma once
// Statistics of measured values and point sets that calibration takes everywhere: the median of a
// sensor's spacings or jitters, and the centroid and principal axes of a segment's points (a plane's
// normal, a line's direction, a board's longer side).

#include <vector>

#include <Eigen/Core>

namespace vocal {

// The upper median (the middle element of an odd count); 0 for none.
double median(std::vector<double> values);

// The mean point; zero for none.
Eigen::Vector3d centroidOf(const std::vector<Eigen::Vector3d>& points);

struct PrincipalAxes {
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
  // Columns by decreasing spread: the first is a line's direction, the last a plane's normal.
  Eigen::Matrix3d axes = Eigen::Matrix3d::Identity();
  Eigen::Vector3d spread = Eigen::Vector3d::Zero();  // the scatter matrix's eigenvalues, in the axes' order
};

PrincipalAxes principalAxesOf(const std::vector<Eigen::Vector3d>& points);

}  // namespace vocal
