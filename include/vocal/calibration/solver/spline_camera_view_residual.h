#pragma once
// A camera's view of a fixed board against the body's spline (camera_imu_calibration.h): its PnP pose
// against (world <- body at the view's time on the IMU's clock, times body <- camera)^-1, the board's
// frame being the world, whitened by the view's PnP covariance. The view's time moves with the time
// offset being solved (IMU stamp = camera stamp + offset), so the offset is fixed by where along the
// motion the view fits.

#include <array>

#include <Eigen/Cholesky>
#include <Eigen/Geometry>

#include "vocal/calibration/calibration_types.h"
#include "vocal/calibration/solver/cumulative_bspline.h"
#include "vocal/calibration/solver/rotation_error.h"

namespace vocal {

// camera <- board (the world) at fraction u of a segment: the body's spline there times the camera's pose in
// the body, inverted. `q`, `p`: the segment's control rotations and positions.
template <typename T>
void cameraFromBoardAt(const std::array<const T*, 4>& q, const std::array<const T*, 4>& p, const T* camera_q, const T* camera_t, const T& u,
                       double spacing, Eigen::Quaternion<T>* rotation, Eigen::Matrix<T, 3, 1>* translation) {
  const SplineRotation<T> body = evaluateRotationSpline<T>(q, u, spacing);
  const SplinePosition<T> body_position = evaluatePositionSpline<T>(p, u, spacing);
  const Eigen::Map<const Eigen::Quaternion<T>> in_body_q(camera_q);
  const Eigen::Map<const Eigen::Matrix<T, 3, 1>> in_body_t(camera_t);
  const Eigen::Quaternion<T> world_q = body.rotation * in_body_q;
  const Eigen::Matrix<T, 3, 1> world_t = body.rotation * in_body_t + body_position.position;
  *rotation = world_q.conjugate();
  *translation = -(*rotation * world_t);
}

struct SplineCameraViewResidual {
  // `segment_start`: the IMU-clock time segment `segment` of the spline begins at; `stamp` the view's
  // camera-clock time.
  SplineCameraViewResidual(const PlaneMeasurement& view, double stamp, double segment_start, double spacing)
      : rotation(view.sensor_from_pattern.linear()), translation(view.sensor_from_pattern.translation()), stamp(stamp),
        segment_start(segment_start), spacing(spacing) {
    whitening = view.pose_covariance.llt().matrixL().solve(Eigen::Matrix<double, 6, 6>::Identity());
  }

  // Blocks: the segment's four rotations and four positions, the camera's rotation and translation in the
  // body (IMU) frame, the time offset (seconds).
  template <typename T>
  bool operator()(const T* q0, const T* q1, const T* q2, const T* q3, const T* p0, const T* p1, const T* p2, const T* p3,
                  const T* camera_q, const T* camera_t, const T* time_offset, T* residual) const {
    using Quaternion = Eigen::Quaternion<T>;
    using Vector = Eigen::Matrix<T, 3, 1>;
    const T u = (T(stamp) + time_offset[0] - T(segment_start)) / T(spacing);
    Quaternion predicted_q;
    Vector predicted_t;
    cameraFromBoardAt<T>({q0, q1, q2, q3}, {p0, p1, p2, p3}, camera_q, camera_t, u, spacing, &predicted_q, &predicted_t);
    Eigen::Matrix<T, 6, 1> r;
    r.template head<3>() = rotationBetween(Quaternion(rotation.cast<T>()), predicted_q);
    r.template tail<3>() = predicted_t - translation.cast<T>();
    Eigen::Map<Eigen::Matrix<T, 6, 1>> out(residual);
    out = whitening.cast<T>() * r;
    return true;
  }

  Eigen::Matrix3d rotation;
  Eigen::Vector3d translation;
  double stamp, segment_start, spacing;
  Eigen::Matrix<double, 6, 6> whitening;
};

}  // namespace vocal
