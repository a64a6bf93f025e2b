#pragma once
// A body's pose as a continuous function of time (camera_imu_calibration.h): a uniform cubic cumulative
// B-spline on SO(3) and one on R^3 (the split form, as Kalibr and basalt fit an IMU's motion), evaluated
// with Ceres jets so the unknowns are its control points. Angular velocity by Sommer et al.'s recursion
// ("Efficient derivative computation for cumulative B-splines on Lie groups", CVPR 2020), acceleration by
// the basis's second derivative.
//
// Segment s covers [start + s * spacing, start + (s + 1) * spacing) and blends control points s .. s + 3;
// control point k lies near start + (k - 1) * spacing. A spline of n control points spans n - 3 segments.

#include <array>
#include <cmath>

#include <Eigen/Geometry>
#include <ceres/rotation.h>

namespace vocal {

// The cumulative basis at u in [0, 1): lambda_j(u) for j = 1..3 (lambda_0 = 1) and its first and second
// derivatives in u.
template <typename T>
struct CumulativeCubicBasis {
  explicit CumulativeCubicBasis(const T& u) {
    const T u2 = u * u, u3 = u2 * u;
    value = {(T(5) + T(3) * u - T(3) * u2 + u3) / T(6), (T(1) + T(3) * u + T(3) * u2 - T(2) * u3) / T(6), u3 / T(6)};
    first = {(T(3) - T(6) * u + T(3) * u2) / T(6), (T(3) + T(6) * u - T(6) * u2) / T(6), T(3) * u2 / T(6)};
    second = {(T(-6) + T(6) * u) / T(6), (T(6) - T(12) * u) / T(6), T(6) * u / T(6)};
  }
  std::array<T, 3> value, first, second;
};

// Where a time falls: the segment and the fraction u of it (not clamped: a time a little outside a
// segment extrapolates its polynomial smoothly, which a time offset being solved needs).
struct SplineSegment {
  int index = 0;
  double u = 0.0;
};

struct SplineKnots {
  double start = 0.0;    // seconds: segment 0 begins here
  double spacing = 0.1;  // seconds between control points
  int control_points = 4;
  int segments() const { return control_points - 3; }
  // The segment holding time t, clamped to the spline's segments.
  SplineSegment segmentAt(double t) const {
    int s = static_cast<int>(std::floor((t - start) / spacing));
    s = s < 0 ? 0 : (s > segments() - 1 ? segments() - 1 : s);
    return {s, (t - start) / spacing - s};
  }
  // The time control point k lies near (where its value is the spline's largest weight).
  double controlPointTime(int k) const { return start + (k - 1) * spacing; }
};

// The rotation spline's value and body angular velocity on one segment. `q` are the segment's four
// control rotations (Eigen quaternions' coefficient arrays, x y z w), u the fraction, spacing in seconds.
template <typename T>
struct SplineRotation {
  Eigen::Quaternion<T> rotation;        // world <- body
  Eigen::Matrix<T, 3, 1> angular_velocity;  // body frame, rad/s
};

template <typename T>
SplineRotation<T> evaluateRotationSpline(const std::array<const T*, 4>& q, const T& u, double spacing) {
  const CumulativeCubicBasis<T> basis(u);
  Eigen::Quaternion<T> rotation = Eigen::Map<const Eigen::Quaternion<T>>(q[0]);
  Eigen::Matrix<T, 3, 1> omega = Eigen::Matrix<T, 3, 1>::Zero();
  for (int j = 1; j <= 3; ++j) {
    const Eigen::Quaternion<T> previous = Eigen::Map<const Eigen::Quaternion<T>>(q[j - 1]);
    const Eigen::Quaternion<T> next = Eigen::Map<const Eigen::Quaternion<T>>(q[j]);
    Eigen::Quaternion<T> delta = previous.conjugate() * next;
    // The shorter way round (q and -q are one rotation; the log must not take the long one).
    if (delta.w() < T(0)) delta.coeffs() = -delta.coeffs();
    const T wxyz[4] = {delta.w(), delta.x(), delta.y(), delta.z()};
    Eigen::Matrix<T, 3, 1> d;
    ceres::QuaternionToAngleAxis(wxyz, d.data());
    const Eigen::Matrix<T, 3, 1> scaled = d * basis.value[j - 1];
    T step_wxyz[4];
    ceres::AngleAxisToQuaternion(scaled.data(), step_wxyz);
    const Eigen::Quaternion<T> step(step_wxyz[0], step_wxyz[1], step_wxyz[2], step_wxyz[3]);
    rotation = rotation * step;
    omega = step.conjugate() * omega + d * (basis.first[j - 1] / T(spacing));
  }
  return {rotation, omega};
}

// The position spline's value and acceleration (world frame) on one segment: `p` the four control points.
template <typename T>
struct SplinePosition {
  Eigen::Matrix<T, 3, 1> position, acceleration;
};

template <typename T>
SplinePosition<T> evaluatePositionSpline(const std::array<const T*, 4>& p, const T& u, double spacing) {
  const CumulativeCubicBasis<T> basis(u);
  using Vector = Eigen::Matrix<T, 3, 1>;
  SplinePosition<T> out{Eigen::Map<const Vector>(p[0]), Vector::Zero()};
  for (int j = 1; j <= 3; ++j) {
    const Vector difference = Eigen::Map<const Vector>(p[j]) - Eigen::Map<const Vector>(p[j - 1]);
    out.position += difference * basis.value[j - 1];
    out.acceleration += difference * (basis.second[j - 1] / T(spacing * spacing));
  }
  return out;
}

}  // namespace vocal
