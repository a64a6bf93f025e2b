#include "vocal/simulation/waved_camera_imu.h"

#include <array>
#include <cmath>
#include <random>

#include "vocal/core/errors.h"
#include "vocal/core/se3.h"
#include "vocal/simulation/simulated_imu.h"

namespace vocal {

namespace {

constexpr double kTwoPi = 6.283185307179586;

// Per axis, two sinusoids: value, first and second derivative at t.
struct Wave {
  std::array<Eigen::Vector3d, 2> amplitude, frequency, phase;
  Eigen::Vector3d value(double t) const { return sum(t, 0); }
  Eigen::Vector3d rate(double t) const { return sum(t, 1); }
  Eigen::Vector3d acceleration(double t) const { return sum(t, 2); }

 private:
  Eigen::Vector3d sum(double t, int derivative) const {
    Eigen::Vector3d out = Eigen::Vector3d::Zero();
    for (int k = 0; k < 2; ++k) {
      for (int a = 0; a < 3; ++a) {
        const double w = kTwoPi * frequency[k][a], x = w * t + phase[k][a];
        const double terms[3] = {std::sin(x), w * std::cos(x), -w * w * std::sin(x)};
        out[a] += amplitude[k][a] * terms[derivative];
      }
    }
    return out;
  }
};

Wave randomWave(const Eigen::Vector3d& amplitude, std::mt19937& random) {
  std::uniform_real_distribution<double> frequency(0.2, 1.2), phase(0.0, kTwoPi);
  Wave wave;
  for (int k = 0; k < 2; ++k) {
    wave.amplitude[k] = amplitude * (k == 0 ? 0.6 : 0.4);
    for (int a = 0; a < 3; ++a) {
      wave.frequency[k][a] = frequency(random);
      wave.phase[k][a] = phase(random);
    }
  }
  return wave;
}

// SO(3)'s right Jacobian: d/dt Exp(phi) = Exp(phi) [J_r(phi) phi']x.
Eigen::Matrix3d rightJacobian(const Eigen::Vector3d& phi) {
  const double angle = phi.norm();
  const Eigen::Matrix3d k = skew(phi);
  if (angle < 1e-8) return Eigen::Matrix3d::Identity() - 0.5 * k;
  return Eigen::Matrix3d::Identity() - (1.0 - std::cos(angle)) / (angle * angle) * k +
         (angle - std::sin(angle)) / (angle * angle * angle) * k * k;
}

}  // namespace

WavedCameraImuSession simulateWavedCameraImu(const WavedCameraImuOptions& o) {
  if (!(o.duration > 0.0 && o.camera_rate > 0.0 && o.imu_rate > 0.0)) {
    throw InputError("waved camera-IMU simulation: duration and rates must be positive");
  }
  std::mt19937 random(o.seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  WavedCameraImuSession session;
  session.time_offset = o.time_offset;
  if (o.camera_in_imu_given) {
    session.camera_in_imu = o.camera_in_imu;
  } else {
    // A D435i's IMU beside its colour camera, mounted a little crooked and further off than its datasheet's
    // 15 mm (so the lever arm is felt on every axis).
    session.camera_in_imu = simulatedImuExtrinsics().camera_in_imu;
    session.camera_in_imu.linear() = session.camera_in_imu.linear() * so3Exp(Eigen::Vector3d(0.012, -0.02, 0.008));
    session.camera_in_imu.translation() = Eigen::Vector3d(0.021, -0.034, 0.012);
  }
  const Eigen::Matrix3d imu_from_camera = session.camera_in_imu.linear();
  const Eigen::Vector3d camera_to_imu_in_camera = session.camera_in_imu.inverse().translation();

  // The camera, at the motion's centre, faces the board square on from `distance` on the side its z axis
  // points to (its printed face: camera x and z opposite the board's); the board leans back 0.1 rad, its y
  // axis down.
  const Eigen::Matrix3d facing = Eigen::Vector3d(-1.0, 1.0, -1.0).asDiagonal();
  const Eigen::Vector3d turn_amplitude =
      o.motion == WavedMotion::kNoTurns ? Eigen::Vector3d::Zero()
      : o.motion == WavedMotion::kOneAxisTurns ? Eigen::Vector3d(0.0, 0.0, 1.5 * o.turn_amplitude)
                                               : Eigen::Vector3d(o.turn_amplitude, o.turn_amplitude, 1.5 * o.turn_amplitude);
  const Wave turn = randomWave(turn_amplitude, random);
  const Wave move = randomWave(Eigen::Vector3d::Constant(o.move_amplitude), random);
  const Eigen::Vector3d centre_of_imu = Eigen::Vector3d(0.0, 0.0, o.distance) + facing * camera_to_imu_in_camera;
  session.gravity_in_board = 9.80665 * (so3Exp(Eigen::Vector3d(0.1, 0.0, 0.0)) * Eigen::Vector3d::UnitY());
  // board <- camera = facing Exp(turn); board <- IMU = board <- camera * camera <- IMU; the IMU's position waves.
  auto boardFromCamera = [&](double t) {
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.linear() = facing * so3Exp(turn.value(t));
    pose.translation() = centre_of_imu + move.value(t) - pose.linear() * camera_to_imu_in_camera;
    return pose;
  };

  // IMU samples over the camera's span and a little beyond, at true time t, stamped t + offset.
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  Eigen::Vector3d gyro_bias, accel_bias;
  for (int a = 0; a < 3; ++a) {
    gyro_bias[a] = o.gyro_bias_limit * unit(random);
    accel_bias[a] = o.accel_bias_limit * unit(random);
  }
  const double dt = 1.0 / o.imu_rate;
  const double gyro_sigma = o.noise.gyro_noise_density * std::sqrt(o.imu_rate);
  const double accel_sigma = o.noise.accel_noise_density * std::sqrt(o.imu_rate);
  const double gyro_walk = o.noise.gyro_bias_random_walk * std::sqrt(dt), accel_walk = o.noise.accel_bias_random_walk * std::sqrt(dt);
  const double padding = 0.5;
  const int samples = static_cast<int>(std::floor((o.duration + 2 * padding) * o.imu_rate));
  for (int j = 0; j < samples; ++j) {
    const double t = -padding + j * dt;
    const Eigen::Vector3d phi = turn.value(t);
    const Eigen::Matrix3d board_from_imu = facing * so3Exp(phi) * imu_from_camera.transpose();
    ImuSample s;
    s.stamp = t + o.time_offset;
    const Eigen::Vector3d camera_rate = rightJacobian(phi) * turn.rate(t);
    s.angular_velocity = imu_from_camera * camera_rate + gyro_bias;
    s.linear_acceleration = board_from_imu.transpose() * (move.acceleration(t) - session.gravity_in_board) + accel_bias;
    for (int a = 0; a < 3; ++a) {
      s.angular_velocity[a] += gyro_sigma * normal(random);
      s.linear_acceleration[a] += accel_sigma * normal(random);
    }
    session.imu.push_back(s);
    session.gyro_bias += gyro_bias / samples;
    session.accel_bias += accel_bias / samples;
    for (int a = 0; a < 3; ++a) {
      gyro_bias[a] += gyro_walk * normal(random);
      accel_bias[a] += accel_walk * normal(random);
    }
  }

  // Camera frames: the board's corners through the lens, with pixel noise, fitted by PnP.
  const std::vector<Eigen::Vector3d> corners = o.pattern.corners();
  const int frames = static_cast<int>(std::floor(o.duration * o.camera_rate)) + 1;
  for (int k = 0; k < frames; ++k) {
    const double t = k / o.camera_rate;
    ++session.frames;
    session.frame_stamps.push_back(t);
    session.board_from_camera.push_back(boardFromCamera(t));
    const Eigen::Isometry3d camera_from_board = session.board_from_camera.back().inverse();
    std::vector<Eigen::Vector2d> pixels;
    bool in_view = true;
    for (const Eigen::Vector3d& corner : corners) {
      const Eigen::Vector3d p = camera_from_board * corner;
      if (p.z() < 0.1) {
        in_view = false;
        break;
      }
      Eigen::Vector2d pixel = projectThroughLens(o.camera, o.lens, p);
      if (pixel.x() < 5 || pixel.y() < 5 || pixel.x() > o.camera.width - 6 || pixel.y() > o.camera.height - 6) {
        in_view = false;
        break;
      }
      pixel += o.pixel_noise * Eigen::Vector2d(normal(random), normal(random));
      pixels.push_back(pixel);
    }
    if (!in_view) continue;
    try {
      const PatternObservation seen = observePattern(pixels, o.pattern, o.camera, "simulated camera", o.lens);
      session.views.push_back(cameraImuView(t, seen, std::move(pixels)));
    } catch (const InputError&) {
      // A view PnP cannot fit is one a detector would have missed.
    }
  }
  return session;
}

}  // namespace vocal
