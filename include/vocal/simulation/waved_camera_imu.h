#pragma once
// A camera and an IMU waved together before a fixed board, as Kalibr users record a camera-IMU session:
// the body's motion a sum of sinusoids per axis (0.2-1.2 Hz, turning about and moving along all three
// axes), so its angular velocity and acceleration are exact; the IMU's samples through a consumer MEMS
// noise model (white noise at the densities, biases drawn per run and walking), stamped on a clock
// `time_offset` ahead of the camera's; each camera frame's board corners projected through its lens with
// pixel noise and fitted by PnP (observePattern), frames whose board leaves the image dropped.

#include <cstdint>
#include <vector>

#include <Eigen/Geometry>

#include "vocal/calibration/extraction/pattern_observation.h"
#include "vocal/calibration/solver/camera_imu_calibration.h"
#include "vocal/core/imu_samples.h"
#include "vocal/core/lens_distortion.h"
#include "vocal/core/pinhole_camera.h"

namespace vocal {

enum class WavedMotion {
  kAllAxes,       // turns about and moves along every axis: what a calibration needs
  kOneAxisTurns,  // turns about the camera's optical axis only (moves along all three)
  kNoTurns,       // moves along all three axes, never turns
};

struct WavedCameraImuOptions {
  double duration = 60.0;     // seconds
  double camera_rate = 20.0;  // Hz
  double imu_rate = 200.0;    // Hz
  double time_offset = 0.01;  // seconds: IMU stamp = camera stamp + time_offset
  ImuNoise noise;             // consumer MEMS (a D435i's BMI055) by default
  double gyro_bias_limit = 0.5 * 3.14159265358979 / 180.0;  // rad/s: each axis's initial bias within +-this
  double accel_bias_limit = 0.05;                           // m/s^2
  // The camera's optical frame in the IMU frame; default: simulatedImuExtrinsics()'s (a D435i's).
  Eigen::Isometry3d camera_in_imu = Eigen::Isometry3d::Identity();
  bool camera_in_imu_given = false;
  PinholeCamera camera{640, 480, 460.0, 460.0, 319.5, 239.5, 1000.0};
  LensDistortion lens{DistortionModel::kPlumbBob, {-0.28, 0.07, 0.0002, -0.0001, 0.0}};
  TargetPattern pattern{6, 7, 0.05};  // a 6 x 7 inner-corner board of 5 cm squares
  double pixel_noise = 0.2;           // px, per corner coordinate
  double distance = 0.9;              // metres from the board at the motion's centre
  double turn_amplitude = 0.3;        // radians per axis (the sum of its sinusoids)
  double move_amplitude = 0.15;       // metres per axis
  WavedMotion motion = WavedMotion::kAllAxes;
  std::uint32_t seed = 1;
};

struct WavedCameraImuSession {
  std::vector<CameraImuView> views;  // frames with the whole board in view, camera clock
  std::vector<ImuSample> imu;        // IMU clock
  int frames = 0;                    // camera frames taken, the board in view or not
  // Every frame's stamp (camera clock) and the camera's pose in the board's frame then (to render it).
  std::vector<double> frame_stamps;
  std::vector<Eigen::Isometry3d> board_from_camera;
  // The truth.
  Eigen::Isometry3d camera_in_imu = Eigen::Isometry3d::Identity();
  double time_offset = 0.0;
  Eigen::Vector3d gyro_bias = Eigen::Vector3d::Zero(), accel_bias = Eigen::Vector3d::Zero();  // their mean over the session
  Eigen::Vector3d gravity_in_board = Eigen::Vector3d::Zero();
};

WavedCameraImuSession simulateWavedCameraImu(const WavedCameraImuOptions& options);

}  // namespace vocal
