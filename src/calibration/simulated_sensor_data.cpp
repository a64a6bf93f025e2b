#include "vocal/calibration/simulated_sensor_data.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace vocal {

namespace {
constexpr double kMaxRange = 8.0;
constexpr double kWallX = 4.5;

enum class Surface { kNone, kTarget, kFloor, kWall };

struct Hit {
  double range = std::numeric_limits<double>::infinity();
  Surface surface = Surface::kNone;
  Eigen::Vector2d on_target = Eigen::Vector2d::Zero();  // target-frame x, y
};

// The nearest surface along a ray from the sensor (direction in the sensor frame).
Hit castRay(const SimulatedRoomView& view, const Eigen::Vector3d& direction) {
  const Eigen::Isometry3d& pose = view.sensor->reference_from_sensor;
  const Eigen::Vector3d origin = pose.translation();
  const Eigen::Vector3d d = pose.linear() * direction.normalized();
  Hit hit;
  auto consider = [&](double range, Surface surface) {
    if (range > 0.05 && range < std::min(hit.range, kMaxRange)) hit.range = range, hit.surface = surface;
  };
  if (std::abs(d.z()) > 1e-9) consider(-origin.z() / d.z(), Surface::kFloor);
  if (std::abs(d.x()) > 1e-9) consider((kWallX - origin.x()) / d.x(), Surface::kWall);
  const Eigen::Vector3d normal = view.reference_from_target.linear().col(2);
  const double denominator = normal.dot(d);
  if (std::abs(denominator) > 1e-9) {
    const double range = normal.dot(view.reference_from_target.translation() - origin) / denominator;
    const Eigen::Vector3d local = view.reference_from_target.inverse() * (origin + range * d);
    if (std::abs(local.x()) <= 0.5 * view.target->width && std::abs(local.y()) <= 0.5 * view.target->height &&
        range > 0.05 && range < std::min(hit.range, kMaxRange)) {
      hit.range = range;
      hit.surface = Surface::kTarget;
      hit.on_target = local.head<2>();
    }
  }
  return hit;
}

double noisy(double range, double sigma, std::mt19937* rng) {
  if (sigma <= 0.0) return range;
  return range + std::normal_distribution<double>(0.0, sigma)(*rng);
}

// Grey level of the board at target-frame (x, y): checker squares centred on the board, white margin.
double boardGrey(const TargetPattern& pattern, const Eigen::Vector2d& p) {
  const double half_w = 0.5 * (pattern.cols + 1) * pattern.square_size, half_h = 0.5 * (pattern.rows + 1) * pattern.square_size;
  if (std::abs(p.x()) >= half_w || std::abs(p.y()) >= half_h) return 235.0;
  const int i = static_cast<int>(std::floor((p.x() + half_w) / pattern.square_size));
  const int j = static_cast<int>(std::floor((p.y() + half_h) / pattern.square_size));
  return (i + j) % 2 == 0 ? 20.0 : 235.0;
}
}  // namespace

std::vector<float> simulateLaserRanges(const SimulatedRoomView& view, std::mt19937* rng) {
  std::vector<float> ranges;
  for (int step = 0; step <= 1080; ++step) {
    const double azimuth = (-135.0 + 0.25 * step) * M_PI / 180.0;
    const Hit hit = castRay(view, Eigen::Vector3d(std::cos(azimuth), std::sin(azimuth), 0.0));
    ranges.push_back(hit.surface == Surface::kNone ? std::numeric_limits<float>::infinity()
                                                   : static_cast<float>(noisy(hit.range, view.range_noise, rng)));
  }
  return ranges;
}

std::vector<Eigen::Vector3d> simulateLidarCloud(const SimulatedRoomView& view, std::mt19937* rng) {
  std::vector<Eigen::Vector3d> points;
  for (int ring = 0; ring < 16; ++ring) {
    const double elevation = (-15.0 + 2.0 * ring) * M_PI / 180.0;
    for (int step = 0; step < 1800; ++step) {
      const double azimuth = step * 0.2 * M_PI / 180.0 - M_PI;
      const Eigen::Vector3d ray(std::cos(elevation) * std::cos(azimuth), std::cos(elevation) * std::sin(azimuth), std::sin(elevation));
      const Hit hit = castRay(view, ray);
      if (hit.surface != Surface::kNone) points.push_back(noisy(hit.range, view.range_noise, rng) * ray);
    }
  }
  return points;
}

DepthImage simulateDepthImage(const SimulatedRoomView& view, const PinholeCamera& camera, std::mt19937* rng) {
  DepthImage depth(camera.width, camera.height, 0.0f);
  for (int v = 0; v < camera.height; ++v) {
    for (int u = 0; u < camera.width; ++u) {
      const Eigen::Vector3d ray((u - camera.cx) / camera.fx, (v - camera.cy) / camera.fy, 1.0);
      const Hit hit = castRay(view, ray);
      if (hit.surface == Surface::kNone) continue;
      // Range noise along the ray, stored as depth (z).
      depth(u, v) = static_cast<float>(noisy(hit.range, view.range_noise, rng) / ray.norm());
    }
  }
  return depth;
}

CameraRays::CameraRays(const PinholeCamera& camera, const LensDistortion& distortion) : camera_(camera) {
  rays_.resize(static_cast<std::size_t>(camera.width) * camera.height * 4);
  for (int v = 0; v < camera.height; ++v) {
    // Each subsample's ideal ray starts Newton from the same subsample of the pixel to the left.
    Eigen::Vector2d previous[4];
    for (int u = 0; u < camera.width; ++u) {
      int sample = 0;
      for (const double du : {-0.25, 0.25}) {
        for (const double dv : {-0.25, 0.25}) {
          const Eigen::Vector2d distorted((u + du - camera.cx) / camera.fx, (v + dv - camera.cy) / camera.fy);
          const Eigen::Vector2d ideal = distortion.undistort(distorted, u == 0 ? distorted : previous[sample]);
          previous[sample] = ideal;
          rays_[(static_cast<std::size_t>(v) * camera.width + u) * 4 + sample++] = Eigen::Vector3d(ideal.x(), ideal.y(), 1.0);
        }
      }
    }
  }
}

ColorImage simulateCameraImage(const SimulatedRoomView& view, const CameraRays& rays, double noise_levels,
                               std::mt19937* rng) {
  const PinholeCamera& camera = rays.camera();
  ColorImage image(camera.width, camera.height);
  std::normal_distribution<double> noise(0.0, std::max(noise_levels, 1e-12));
  for (int v = 0; v < camera.height; ++v) {
    for (int u = 0; u < camera.width; ++u) {
      double grey = 0.0;
      for (int sample = 0; sample < 4; ++sample) {
        const Hit hit = castRay(view, rays.ray(u, v, sample));
        grey += 0.25 * (hit.surface == Surface::kTarget ? boardGrey(view.target->pattern, hit.on_target)
                        : hit.surface == Surface::kNone ? 60.0
                                                         : 120.0);
      }
      if (noise_levels > 0.0) grey += noise(*rng);
      const auto level = static_cast<std::uint8_t>(std::clamp(std::lround(grey), 0L, 255L));
      image(u, v) = Rgb8{level, level, level};
    }
  }
  return image;
}

ColorImage simulateCameraImage(const SimulatedRoomView& view, const PinholeCamera& camera, double noise_levels,
                               std::mt19937* rng, const LensDistortion& distortion) {
  return simulateCameraImage(view, CameraRays(camera, distortion), noise_levels, rng);
}

}  // namespace vocal
