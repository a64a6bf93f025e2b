#pragma once
// A camera's view of the board in the arm's graph (hand_eye_calibration.h): its PnP pose against the pose
// the unknowns predict, whitened by the view's covariance.

#include <Eigen/Cholesky>
#include <Eigen/Geometry>

#include "vocal/calibration/calibration_types.h"
#include "vocal/calibration/solver/frame_mounting.h"
#include "vocal/calibration/solver/rotation_error.h"

namespace vocal {

// camera <- board = X^-1 M, M the board in the camera's parent (FrameMounting), as (w, dt) whitened by the
// view's PnP covariance. Blocks: the camera's rotation and translation in its parent, the board's in its
// own, the frame the camera moves with, the frame the board moves with (each a quaternion and a vector).
struct CameraViewResidual {
  CameraViewResidual(const PlaneMeasurement& view, FrameMounting mounting)
      : rotation(view.sensor_from_pattern.linear()), translation(view.sensor_from_pattern.translation()), mounting(mounting) {
    whitening = view.pose_covariance.llt().matrixL().solve(Eigen::Matrix<double, 6, 6>::Identity());
  }

  template <typename T>
  bool operator()(const T* xq, const T* xt, const T* yq, const T* yt, const T* sq, const T* st, const T* bq, const T* bt, T* residual) const {
    using Quaternion = Eigen::Quaternion<T>;
    using Vector = Eigen::Matrix<T, 3, 1>;
    const Eigen::Map<const Quaternion> camera_q(xq);
    const Eigen::Map<const Vector> camera_t(xt);
    const T* board[] = {yq, yt, sq, st, bq, bt};
    const auto [q, t] = mounting.boardInSensorParent(board);
    Eigen::Matrix<T, 6, 1> r;
    r.template head<3>() = rotationBetween(Quaternion(rotation.cast<T>()), Quaternion(camera_q.conjugate() * q));
    r.template tail<3>() = camera_q.conjugate() * (t - camera_t) - translation.cast<T>();
    Eigen::Map<Eigen::Matrix<T, 6, 1>> out(residual);
    out = whitening.cast<T>() * r;
    return true;
  }

  Eigen::Matrix3d rotation;
  Eigen::Vector3d translation;
  FrameMounting mounting;
  Eigen::Matrix<double, 6, 6> whitening;
};

}  // namespace vocal
