// Camera-IMU calibration on simulated waved sessions (simulation/waved_camera_imu.h): per seed, the
// camera's pose in the IMU frame and the clock offset against the truth, the stated standard deviations,
// and the wall time of the solve. Usage: camera_imu_sessions [--duration S] [--seeds N] [--imu-rate HZ]
//   [--camera-rate HZ] [--knot-spacing S] [--corners 1]
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "vocal/calibration/solver/camera_imu_calibration.h"
#include "vocal/core/errors.h"
#include "vocal/core/se3.h"
#include "vocal/simulation/waved_camera_imu.h"

int main(int argc, char** argv) {
  using namespace vocal;
  WavedCameraImuOptions session_options;
  CameraImuOptions options;
  int seeds = 3;
  bool corners = false;  // the corners through the lens instead of the PnP poses
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string flag = argv[i];
    const double value = std::atof(argv[i + 1]);
    if (flag == "--duration") session_options.duration = value;
    else if (flag == "--seeds") seeds = static_cast<int>(value);
    else if (flag == "--imu-rate") session_options.imu_rate = value;
    else if (flag == "--camera-rate") session_options.camera_rate = value;
    else if (flag == "--knot-spacing") options.knot_spacing = value;
    else if (flag == "--corners") corners = value != 0.0;
    else {
      std::fprintf(stderr, "camera_imu_sessions: unknown flag %s\n", argv[i]);
      return 2;
    }
  }
  const double offsets[] = {0.005, -0.012, 0.02, 0.015, -0.008};
  std::printf("| seed | offset (truth) ms | views / frames | IMU samples | camera in IMU: mm / mrad (sigma) | offset error ms (sigma) | gyro bias error rad/s | closed form: deg / ms | solve s |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|\n");
  for (int seed = 1; seed <= seeds; ++seed) {
    session_options.seed = static_cast<std::uint32_t>(seed);
    session_options.time_offset = offsets[(seed - 1) % 5];
    const WavedCameraImuSession session = simulateWavedCameraImu(session_options);
    if (corners) options.camera_model = CameraImuCameraModel{session_options.camera, session_options.lens, session_options.pattern};
    const auto start = std::chrono::steady_clock::now();
    try {
      const CameraImuResult r = calibrateCameraImu(session.views, session.imu, session_options.noise, options);
      const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      const Eigen::Isometry3d error = session.camera_in_imu.inverse() * r.camera_in_imu;
      const double initial_angle = so3Log(r.initial_rotation.transpose() * session.camera_in_imu.linear()).norm();
      std::printf("| %d | %.1f | %d / %d | %d | %.3f / %.3f (%.3f / %.3f) | %.3f (%.3f) | %.1e | %.2f / %.2f | %.1f |%s%s\n", seed,
                  session.time_offset * 1000, r.views, session.frames, r.imu_samples, error.translation().norm() * 1000,
                  rotationAngle(error) * 1000, r.sigma.head<3>().norm() * 1000, r.sigma.tail<3>().norm() * 1000,
                  (r.time_offset - session.time_offset) * 1000, r.time_offset_sigma * 1000,
                  (r.gyro_bias - session.gyro_bias).cwiseAbs().maxCoeff(), initial_angle * 57.29578,
                  (r.initial_time_offset - session.time_offset) * 1000, seconds, r.withheld.empty() ? "" : " withheld: ",
                  r.withheld.c_str());
    } catch (const InputError& e) {
      std::printf("| %d | refused: %s |\n", seed, e.what());
    }
  }
  return 0;
}
