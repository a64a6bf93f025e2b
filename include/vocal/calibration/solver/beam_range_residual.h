#pragma once
// A range sensor's board points against a plane as range errors along each beam, for the Ceres graphs (a
// 2D laser's view in both): Eigen only, so it stays out of Ceres's headers.
//
// A scanner's noise lies along its beams. The point-to-plane distance of a noisy point is that noise
// times the cosine of the beam's incidence, which depends on the sensor's pose: a least-squares fit of
// distances then prefers poses that turn the beams towards grazing (their noise shrinks) - a bias that a
// direction the planes constrain weakly (a 2D laser's height and pitch before boards at similar ranges)
// takes up in full: 18-47 mm on simulated arm sessions with a 1 cm laser. The distance over the
// cosine is the range the beam measured less the range to the plane along it, whose noise does not
// depend on the pose.

#include <vector>

#include <Eigen/Geometry>

namespace vocal {

// Beams whose incidence is more grazing than this cosine count as this (their range error then is at
// most 1 / kLeastBeamCosine times the distance): a pose far from the solution must not divide by zero.
constexpr double kLeastBeamCosine = 0.2;

// One residual per point (sensor frame, the beam from the sensor's origin through it): its range less
// the range along its beam to the plane n . x + d = 0, in `sigma`s. The sensor's pose (q, t) and the
// plane are in one frame.
template <typename T>
void beamRangeResiduals(const std::vector<Eigen::Vector3d>& points, double sigma, const Eigen::Quaternion<T>& q,
                        const Eigen::Matrix<T, 3, 1>& t, const Eigen::Matrix<T, 3, 1>& n, const T& d, T* residuals) {
  const T at_origin = n.dot(t) + d;
  const Eigen::Matrix<T, 3, 1> n_in_sensor = q.conjugate() * n;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const T along_normal = n_in_sensor.dot(points[i].cast<T>());
    T cosine = along_normal / T(points[i].norm());
    if (cosine < T(0.0) && cosine > T(-kLeastBeamCosine)) cosine = T(-kLeastBeamCosine);
    if (cosine >= T(0.0) && cosine < T(kLeastBeamCosine)) cosine = T(kLeastBeamCosine);
    residuals[i] = (along_normal + at_origin) / (cosine * T(sigma));
  }
}

// beamRangeResiduals with the blocks of ObservationOnPlaneResidual (point_plane_residual.h): the sensor's
// rotation (Eigen quaternion) and translation and the plane's normal and offset, in one frame; one residual
// per point. The still-pose graph's 2D laser view (graph_calibration.h).
struct BeamRangePlaneResidual {
  std::vector<Eigen::Vector3d> points;
  double sigma;

  template <typename T>
  bool operator()(const T* rotation, const T* translation, const T* normal, const T* offset, T* residuals) const {
    beamRangeResiduals(points, sigma, Eigen::Quaternion<T>(rotation), Eigen::Matrix<T, 3, 1>(translation), Eigen::Matrix<T, 3, 1>(normal),
                       offset[0], residuals);
    return true;
  }
};

}  // namespace vocal
