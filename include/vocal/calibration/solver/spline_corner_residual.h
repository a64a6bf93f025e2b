#pragma once
// A frame's detected board corners against the body's spline (camera_imu_calibration.h): each corner of
// the fixed board (its frame the world) moved into the camera at the frame's stamp plus the clock offset
// and projected through the camera's lens, its pixel error in the corners' sigma. What the PnP pose with
// its covariance (spline_camera_view_residual.h) says to first order, without the linearisation.

#include <vector>

#include <Eigen/Geometry>

#include "vocal/calibration/solver/spline_camera_view_residual.h"
#include "vocal/core/lens_distortion.h"
#include "vocal/core/pinhole_camera.h"

namespace vocal {

struct SplineCornerResidual {
  // `pixels`: the detected corners (the image as taken), `corners`: the same corners on the board (z = 0).
  SplineCornerResidual(std::vector<Eigen::Vector2d> pixels, std::vector<Eigen::Vector3d> corners, const PinholeCamera& camera,
                       const LensDistortion& lens, double pixel_sigma, double stamp, double segment_start, double spacing)
      : pixels(std::move(pixels)), corners(std::move(corners)), camera(camera), lens(lens), pixel_sigma(pixel_sigma), stamp(stamp),
        segment_start(segment_start), spacing(spacing) {}

  // Blocks as SplineCameraViewResidual's; 2 residuals a corner.
  template <typename T>
  bool operator()(const T* q0, const T* q1, const T* q2, const T* q3, const T* p0, const T* p1, const T* p2, const T* p3,
                  const T* camera_q, const T* camera_t, const T* time_offset, T* residual) const {
    const T u = (T(stamp) + time_offset[0] - T(segment_start)) / T(spacing);
    Eigen::Quaternion<T> rotation;
    Eigen::Matrix<T, 3, 1> translation;
    cameraFromBoardAt<T>({q0, q1, q2, q3}, {p0, p1, p2, p3}, camera_q, camera_t, u, spacing, &rotation, &translation);
    for (std::size_t i = 0; i < corners.size(); ++i) {
      const Eigen::Matrix<T, 3, 1> point = rotation * corners[i].cast<T>() + translation;
      const Eigen::Matrix<T, 2, 1> distorted = distortNormalised<T>(lens, {point.x() / point.z(), point.y() / point.z()});
      residual[2 * i] = (T(camera.fx) * distorted.x() + T(camera.cx) - T(pixels[i].x())) / T(pixel_sigma);
      residual[2 * i + 1] = (T(camera.fy) * distorted.y() + T(camera.cy) - T(pixels[i].y())) / T(pixel_sigma);
    }
    return true;
  }

  std::vector<Eigen::Vector2d> pixels;
  std::vector<Eigen::Vector3d> corners;
  PinholeCamera camera;
  LensDistortion lens;
  double pixel_sigma, stamp, segment_start, spacing;
};

}  // namespace vocal
