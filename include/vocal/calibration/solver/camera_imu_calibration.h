#pragma once
// Camera-IMU calibration (calibration/solver/): a camera and an IMU waved together before a fixed board.
// In:  every camera frame's view of the board (its PnP pose and covariance, camera clock) and the IMU's
//      samples (its clock), with the IMU's noise figures.
// Out: the camera's pose in the IMU frame and the time offset between the clocks (IMU stamp = camera
//      stamp + offset), with standard deviations; the biases; residuals per kind; and whether the motion
//      fixed them (withheld with what to do when not).
//
// As Kalibr (Furgale et al., IROS 2013): the IMU's (body's) pose in the board's frame as a continuous-time
// cumulative B-spline (cumulative_bspline.h), each IMU sample a gyro and accelerometer residual with
// biases on knots a random walk apart and gravity's direction in the board's frame
// (imu_sample_residual.h), each camera view its PnP pose against the spline at its time plus the offset
// (spline_camera_view_residual.h). No guess is needed: the offset comes first from correlating the
// camera's and the gyro's angular speeds, the rotation from aligning their angular velocities (Wahba's
// problem), the translation from zero, gravity from the mean specific force turned into the board's frame.

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "vocal/calibration/calibration_types.h"
#include "vocal/calibration/extraction/pattern_observation.h"
#include "vocal/core/imu_samples.h"
#include "vocal/core/lens_distortion.h"
#include "vocal/core/pinhole_camera.h"

namespace vocal {

// One camera frame's board: its PnP pose and covariance (observePattern) at the frame's stamp, and the
// detected corners it was fitted to (pixels of the image as taken, in TargetPattern::corners()'s order) with
// their noise (the fit's reprojection error).
struct CameraImuView {
  double stamp = 0.0;  // seconds, the camera's clock
  PlaneMeasurement board;
  std::vector<Eigen::Vector2d> corners;
  double pixel_sigma = 0.0;
};
// A frame's view from its detected corners and their PnP fit (observePattern); a view whose fit left a
// misdetected corner out keeps no corners, so the graph holds it by its PnP pose, which leaves that corner out.
CameraImuView cameraImuView(double stamp, const PatternObservation& seen, std::vector<Eigen::Vector2d> corners);


// The camera's model: with it each view's corners are projected through the lens in the graph
// (spline_corner_residual.h); without it, or for a view without corners, its PnP pose with its covariance.
struct CameraImuCameraModel {
  PinholeCamera camera;
  LensDistortion lens;
  TargetPattern pattern;
};

struct CameraImuOptions {
  double knot_spacing = 0.02;       // seconds between the body spline's control points (50 a second: a hand's waving)
  double bias_knot_spacing = 1.0;   // seconds between bias knots
  double max_time_offset = 0.2;     // seconds either way the clocks may differ
  double gravity = 9.80665;         // m/s^2
  int max_iterations = 60;
  int threads = 2;
  // What the motion must show (Kalibr's advice: turn about every axis): the camera's angular velocity's
  // RMS about its least-turned axis, rad/s; under it the rotation and the lever arm are not fixed.
  double min_axis_rate = 0.1;
  // Results whose standard deviations exceed these are withheld.
  double max_translation_sigma = 0.002;  // metres
  double max_rotation_sigma = 0.002;     // radians
  double max_time_offset_sigma = 0.001;  // seconds
  std::optional<CameraImuCameraModel> camera_model;
};

struct CameraImuResult {
  Eigen::Isometry3d camera_in_imu = Eigen::Isometry3d::Identity();  // x_imu = camera_in_imu * x_camera
  double time_offset = 0.0;  // seconds: IMU stamp = camera stamp + time_offset
  // Standard deviations: translation (m) along and rotation (rad) about the IMU frame's axes; the offset's (s).
  Eigen::Matrix<double, 6, 1> sigma = Eigen::Matrix<double, 6, 1>::Zero();
  double time_offset_sigma = 0.0;
  // The closed forms the solve started from.
  Eigen::Matrix3d initial_rotation = Eigen::Matrix3d::Identity();
  double initial_time_offset = 0.0;
  double angular_speed_correlation = 0.0;  // of the camera's and the gyro's, at initial_time_offset
  // The biases over the session (their mean over the bias knots), rad/s and m/s^2; gravity's direction
  // in the board's frame.
  Eigen::Vector3d gyro_bias = Eigen::Vector3d::Zero(), accel_bias = Eigen::Vector3d::Zero();
  Eigen::Vector3d gravity_in_board = Eigen::Vector3d::Zero();
  // Root mean square residuals: gyro (rad/s), accelerometer (m/s^2), camera views (PnP pose: m and rad).
  double gyro_rms = 0.0, accel_rms = 0.0, view_translation_rms = 0.0, view_rotation_rms = 0.0;
  int views = 0, imu_samples = 0, iterations = 0;
  int turned_views = 0;  // views whose board's corners were found the other way round, turned back
  int left_out_views = 0;  // views whose board turned away and straight back (PnP's mirrored solution), left out
  int views_at_rest = 0;   // views outside the span where the gyro turns (the rig at rest), not used
  int views_by_corners = 0;  // views held by their corners through the lens (CameraImuOptions::camera_model)
  std::string withheld;  // why the result is not to be used (empty: it is)
};

// Only the views within the span where the gyro turns are used (a recording may start and end at rest, or
// hold still poses for the rig's other sensors). Throws InputError for fewer than 20 views or 100 IMU samples, stamps not increasing, no overlap of the
// two streams, a motion that cannot fix the rotation (the camera never turns, or turns about one axis
// only: the message says which and what to do), or angular speeds that do not correlate at any offset
// within max_time_offset.
CameraImuResult calibrateCameraImu(const std::vector<CameraImuView>& views, const std::vector<ImuSample>& imu, const ImuNoise& noise,
                                   const CameraImuOptions& options = {});

}  // namespace vocal
