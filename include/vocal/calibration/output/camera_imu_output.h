#pragma once
// A camera-IMU calibration (camera_imu_calibration.h) as the files a user applies: an `imus:` block of the
// result YAML (each IMU in the rig frame, its camera in it, the clock offset, sigmas, residuals), a URDF
// joint and a static transform per IMU (calibration_output.h's), and Kalibr's camchain-imucam.yaml layout
// (T_cam_imu, timeshift_cam_imu) for tools that read Kalibr's results.

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "vocal/calibration/solver/camera_imu_calibration.h"
#include "vocal/core/lens_distortion.h"
#include "vocal/core/pinhole_camera.h"

namespace vocal {

struct ImuCalibrationOutput {
  std::string name, frame_id;
  std::string camera_name, camera_frame, camera_topic;  // the camera it was calibrated against
  PinholeCamera camera;
  LensDistortion lens;
  CameraImuResult result;
  // The IMU in its parent frame: its camera's pose there times the camera in the IMU inverted; none where
  // its camera was not placed.
  std::optional<Eigen::Isometry3d> rig_from_imu;
  // The frame rig_from_imu is in, its camera's parent: empty for the rig's reference frame, an arm's tool or
  // link for a camera the arm moves.
  std::string parent_frame;
  std::string withheld;  // why it stays out of the URDF and launch file (empty: published)
};

// The `imus:` block (a top-level key of calibration.yaml; `reference_frame` the rig's).
std::string imuCalibrationYaml(const std::vector<ImuCalibrationOutput>& imus, const std::string& reference_frame);
// Per IMU, its URDF joint and its static_transform_publisher node, or a comment saying why it is withheld.
std::string imuUrdfJoints(const std::vector<ImuCalibrationOutput>& imus, const std::string& reference_frame);
std::string imuStaticTransformNodes(const std::vector<ImuCalibrationOutput>& imus, const std::string& reference_frame);
// Kalibr's camchain-imucam.yaml: cam0, cam1, ... one per IMU's camera, in order (Kalibr's pinhole model;
// plumb_bob as radtan, equidistant as equidistant). Throws InputError naming the file when it cannot be
// written.
void writeKalibrCamchain(const std::string& path, const std::vector<ImuCalibrationOutput>& imus);

}  // namespace vocal
