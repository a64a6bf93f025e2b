#pragma once
// A board pose of the still-pose graph (graph_calibration.h) held weakly to where it started. Eigen only.

#include <Eigen/Geometry>

namespace vocal {

// Its translation in metres and its turn (twice the quaternion's vector part, the angle for small turns)
// in radians, unwhitened: a standard deviation of 1 m and 1 rad. No say where the sensors place the board,
// but a pose whose place in its plane no sensor's outline fixes (seen by a 2D laser and a lidar's few
// rings) stays defined, so the covariance of everything else can still be computed. Blocks: the board's
// rotation (Eigen quaternion) and translation.
struct WeakBoardPrior {
  Eigen::Quaterniond rotation;
  Eigen::Vector3d translation;
  template <typename T>
  bool operator()(const T* q_data, const T* t_data, T* residual) const {
    const Eigen::Map<const Eigen::Quaternion<T>> q(q_data);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> t(t_data);
    Eigen::Quaternion<T> turn = rotation.conjugate().cast<T>() * q;
    if (turn.w() < T(0)) turn.coeffs() = -turn.coeffs();
    for (int i = 0; i < 3; ++i) residual[i] = t[i] - T(translation[i]), residual[3 + i] = T(2) * turn.vec()[i];
    return true;
  }
};

}  // namespace vocal
