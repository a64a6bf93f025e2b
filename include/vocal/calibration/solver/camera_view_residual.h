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
      : rotation(view.sensor_from_pattern.linear()), translation(view.sensor_from_pattern.translation()),
        pose_per_intrinsics(view.pose_per_intrinsics), mounting(mounting) {
    whitening = view.pose_covariance.llt().matrixL().solve(Eigen::Matrix<double, 6, 6>::Identity());
  }

  template <typename T>
  bool operator()(const T* xq, const T* xt, const T* yq, const T* yt, const T* sq, const T* st, const T* bq, const T* bt, T* residual) const {
    return evaluate<T>(xq, xt, yq, yt, sq, st, bq, bt, nullptr, residual);
  }

  // With the camera's intrinsics changed by `intrinsics` (intrinsics_refinement.h; null: as given), the
  // view as its corners would then put it: R exp([w]x), t + dt.
  template <typename T>
  bool evaluate(const T* xq, const T* xt, const T* yq, const T* yt, const T* sq, const T* st, const T* bq, const T* bt, const T* intrinsics,
                T* residual) const {
    using Quaternion = Eigen::Quaternion<T>;
    using Vector = Eigen::Matrix<T, 3, 1>;
    const Eigen::Map<const Quaternion> camera_q(xq);
    const Eigen::Map<const Vector> camera_t(xt);
    const T* board[] = {yq, yt, sq, st, bq, bt};
    const auto [q, t] = mounting.boardInSensorParent(board);
    Quaternion measured_q(rotation.cast<T>());
    Vector measured_t = translation.cast<T>();
    if (intrinsics) {
      const Eigen::Matrix<T, 6, 1> moved = pose_per_intrinsics.cast<T>() * Eigen::Map<const Eigen::Matrix<T, 4, 1>>(intrinsics);
      T turn[4];
      const Vector w = moved.template head<3>();
      ceres::AngleAxisToQuaternion(w.data(), turn);
      measured_q = measured_q * Quaternion(turn[0], turn[1], turn[2], turn[3]);
      measured_t += moved.template tail<3>();
    }
    Eigen::Matrix<T, 6, 1> r;
    r.template head<3>() = rotationBetween(measured_q, Quaternion(camera_q.conjugate() * q));
    r.template tail<3>() = camera_q.conjugate() * (t - camera_t) - measured_t;
    Eigen::Map<Eigen::Matrix<T, 6, 1>> out(residual);
    out = whitening.cast<T>() * r;
    return true;
  }

  Eigen::Matrix3d rotation;
  Eigen::Vector3d translation;
  Eigen::Matrix<double, 6, 4> pose_per_intrinsics;
  FrameMounting mounting;
  Eigen::Matrix<double, 6, 6> whitening;
};

// The same view with the camera's intrinsics correction (dk, intrinsics_refinement.h) as a ninth block.
struct CameraViewWithIntrinsics {
  CameraViewResidual view;
  template <typename T>
  bool operator()(const T* xq, const T* xt, const T* yq, const T* yt, const T* sq, const T* st, const T* bq, const T* bt, const T* intrinsics,
                  T* residual) const {
    return view.evaluate<T>(xq, xt, yq, yt, sq, st, bq, bt, intrinsics, residual);
  }
};

}  // namespace vocal
