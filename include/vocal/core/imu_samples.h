#pragma once
// An IMU's samples and what the odometry needs to know about it: its noise figures and its pose in the
// camera. The text layout `imu.txt` (`timestamp wx wy wz ax ay az`: seconds, rad/s, m/s^2, in the IMU
// frame, `#` comments) and `imu_extrinsics.yaml` (README, "Odometry with an IMU").

#include <string>
#include <vector>

#include <Eigen/Geometry>

namespace vocal {

struct ImuSample {
  double stamp = 0.0;                                       // seconds, the IMU's clock
  Eigen::Vector3d angular_velocity = Eigen::Vector3d::Zero();  // rad/s, IMU frame
  Eigen::Vector3d linear_acceleration = Eigen::Vector3d::Zero();  // m/s^2 specific force (at rest: up), IMU frame
};

// Continuous-time noise figures (Kalibr's imu.yaml names). The defaults are a consumer MEMS IMU's, a
// RealSense D435i's Bosch BMI055 (gyro 0.014 deg/s/sqrt(Hz), accelerometer 150-190 ug/sqrt(Hz)), with
// random walks as Kalibr users report for it.
struct ImuNoise {
  double gyro_noise_density = 2.4e-4;      // rad/s/sqrt(Hz)
  double gyro_bias_random_walk = 2.0e-5;   // rad/s^2/sqrt(Hz)
  double accel_noise_density = 2.0e-3;     // m/s^2/sqrt(Hz)
  double accel_bias_random_walk = 3.0e-4;  // m/s^3/sqrt(Hz)
};

struct ImuExtrinsics {
  std::string imu_frame = "imu_link";
  std::string camera_frame = "camera_rgb_optical_frame";
  // The camera's optical frame in the IMU frame: x_imu = camera_in_imu * x_camera.
  Eigen::Isometry3d camera_in_imu = Eigen::Isometry3d::Identity();
  double time_offset = 0.0;  // seconds: IMU stamp = camera stamp + time_offset
  ImuNoise noise;
};

// imu.txt. Throws InputError naming the file and line for a malformed line, a value that is not finite
// or a stamp not after the one before.
std::vector<ImuSample> readImuFile(const std::string& path);
void writeImuFile(const std::string& path, const std::vector<ImuSample>& samples);

// imu_extrinsics.yaml. Throws InputError naming the file and the key for a missing or malformed entry
// (a rotation that is not a unit quaternion, a negative noise figure).
ImuExtrinsics readImuExtrinsics(const std::string& path);
void writeImuExtrinsics(const std::string& path, const ImuExtrinsics& extrinsics);

// The samples' mean rate (Hz) over their span; 0 for fewer than two.
double imuRate(const std::vector<ImuSample>& samples);

}  // namespace vocal
