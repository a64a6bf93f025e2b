#pragma once
// One IMU sample against the body's spline (camera_imu_calibration.h): the gyro's angular velocity and
// the accelerometer's specific force as the spline, the biases and gravity predict them, each whitened by
// its discrete noise (noise density times the square root of the rate). The biases are linear between
// two bias knots (a random walk, bias_random_walk_residual.h).

#include <Eigen/Geometry>

#include "vocal/calibration/solver/cumulative_bspline.h"

namespace vocal {

struct ImuSampleResidual {
  ImuSampleResidual(const Eigen::Vector3d& angular_velocity, const Eigen::Vector3d& specific_force, double u, double spacing,
                    double bias_weight, double gyro_sigma, double accel_sigma, double gravity)
      : angular_velocity(angular_velocity), specific_force(specific_force), u(u), spacing(spacing), bias_weight(bias_weight),
        gyro_sigma(gyro_sigma), accel_sigma(accel_sigma), gravity(gravity) {}

  // Blocks: the segment's four rotations (x y z w) and four positions (world = the board's frame), the gyro
  // and accelerometer biases at the bias knots before and after, and gravity's direction (a unit vector,
  // down, world frame).
  template <typename T>
  bool operator()(const T* q0, const T* q1, const T* q2, const T* q3, const T* p0, const T* p1, const T* p2, const T* p3,
                  const T* gyro_bias0, const T* gyro_bias1, const T* accel_bias0, const T* accel_bias1, const T* down,
                  T* residual) const {
    using Vector = Eigen::Matrix<T, 3, 1>;
    const SplineRotation<T> rotation = evaluateRotationSpline<T>({q0, q1, q2, q3}, T(u), spacing);
    const SplinePosition<T> position = evaluatePositionSpline<T>({p0, p1, p2, p3}, T(u), spacing);
    const T w1 = T(bias_weight), w0 = T(1.0 - bias_weight);
    const Vector gyro_bias = Eigen::Map<const Vector>(gyro_bias0) * w0 + Eigen::Map<const Vector>(gyro_bias1) * w1;
    const Vector accel_bias = Eigen::Map<const Vector>(accel_bias0) * w0 + Eigen::Map<const Vector>(accel_bias1) * w1;
    const Vector gravity_vector = Eigen::Map<const Vector>(down) * T(gravity);
    const Vector predicted_rate = rotation.angular_velocity + gyro_bias;
    const Vector predicted_force = rotation.rotation.conjugate() * (position.acceleration - gravity_vector) + accel_bias;
    Eigen::Map<Eigen::Matrix<T, 6, 1>> out(residual);
    out.template head<3>() = (predicted_rate - angular_velocity.cast<T>()) / T(gyro_sigma);
    out.template tail<3>() = (predicted_force - specific_force.cast<T>()) / T(accel_sigma);
    return true;
  }

  Eigen::Vector3d angular_velocity, specific_force;
  double u, spacing, bias_weight, gyro_sigma, accel_sigma, gravity;
};

// Two neighbouring bias knots of one sensor (gyro or accelerometer) a random walk apart: their
// difference whitened by the walk's spread over the knots' interval.
struct BiasRandomWalkResidual {
  explicit BiasRandomWalkResidual(double sigma) : sigma(sigma) {}
  template <typename T>
  bool operator()(const T* before, const T* after, T* residual) const {
    for (int i = 0; i < 3; ++i) residual[i] = (after[i] - before[i]) / T(sigma);
    return true;
  }
  double sigma;
};

}  // namespace vocal
