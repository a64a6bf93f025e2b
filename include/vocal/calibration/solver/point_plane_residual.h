#pragma once
// A range sensor's board points against a plane, for the Ceres graphs (graph_calibration, hand-eye):
// Eigen only, so it stays out of Ceres's headers.

#include <vector>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include "vocal/calibration/calibration_types.h"

namespace vocal {

// All points of one observation on the target's plane (rig frame). The sum over the points of
// (n . (q p + t) + d)^2 equals |F^T v|^2 with v = (q^-1 n, n . t + d) and F F^T the 4x4 moment matrix
// of the homogeneous points, so one block with 4 residuals carries exactly the information of every
// point at the cost of one.
struct ObservationOnPlaneResidual {
  // Residuals are divided by `point_sigma`, so every observation counts by its own noise.
  ObservationOnPlaneResidual(const std::vector<Eigen::Vector3d>& points, double point_sigma) {
    Eigen::Matrix4d moments = Eigen::Matrix4d::Zero();
    for (const Eigen::Vector3d& p : points) {
      const Eigen::Vector4d h(p.x(), p.y(), p.z(), 1.0);
      moments += h * h.transpose();
    }
    // Positive semi-definite (a 2D laser's points span only 3 dimensions): factor by eigenvalues.
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d> eigen(moments);
    factor_transpose =
        (eigen.eigenvalues().cwiseMax(0.0).cwiseSqrt() / point_sigma).asDiagonal() * eigen.eigenvectors().transpose();
  }

  // The sensor at (rotation, translation) in the frame of the plane (normal, offset).
  template <typename T>
  bool operator()(const T* rotation, const T* translation, const T* normal, const T* offset, T* residual) const {
    const Eigen::Map<const Eigen::Quaternion<T>> q(rotation);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> t(translation);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> n(normal);
    Eigen::Matrix<T, 4, 1> v;
    v.template head<3>() = q.conjugate() * n;
    v[3] = n.dot(t) + offset[0];
    Eigen::Map<Eigen::Matrix<T, 4, 1>> out(residual);
    out = factor_transpose.cast<T>() * v;
    return true;
  }

  Eigen::Matrix4d factor_transpose;
};

// A range sensor's point noise from its own points: the RMS distance to their best plane (or, for a
// 2D laser, to their best line in the scan plane), with a floor so noise-free data stays finite.
double estimatedPointSigma(const std::vector<Eigen::Vector3d>& points, SensorType type);

}  // namespace vocal
