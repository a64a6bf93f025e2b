#include "vocal/simulation/simulated_sensor_data.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "vocal/core/errors.h"

namespace vocal {

namespace {
constexpr double kMaxRange = 8.0;
constexpr double kNearerSurface = 0.05;  // metres: a surface this much nearer than a beam's centre's is another

// The room with the view's target in it, and the sensor's origin and axes in the rig frame.
struct SensorInRoom {
  explicit SensorInRoom(const SimulatedRoomView& view)
      : room(view.layout, view.reference_from_target, *view.target, view.person_holds_target, view.board_on_stand),
        pose(view.sensor->reference_from_sensor) {}
  RoomHit cast(const Eigen::Vector3d& direction, const Eigen::Vector3d& origin = Eigen::Vector3d::Zero()) const {
    return room.cast(pose * origin, pose.linear() * direction.normalized(), kMaxRange);
  }
  SimulatedRoom room;
  Eigen::Isometry3d pose;
};

// A hit's range, kMaxRange where the ray hit nothing.
double rangeOf(const RoomHit& hit) { return hit.label == SurfaceLabel::kNone ? kMaxRange : hit.range; }

// A range return along `direction`, with a mixed pixel where the beam's footprint (`direction` +-
// `footprint`) straddles an edge: half the time a range between the two surfaces, labelled mixed
// unless it lies near the centre's surface.
RoomHit rangeReturn(const SensorInRoom& sensor, const SimulatedRoomView& view, const Eigen::Vector3d& direction,
                    const Eigen::Vector3d& footprint, std::mt19937* rng, const Eigen::Vector3d& origin = Eigen::Vector3d::Zero()) {
  RoomHit centre = sensor.cast(direction, origin);
  if (!view.mixed_pixels) return centre;
  RoomHit other = centre;
  for (const double sign : {-1.0, 1.0}) {
    const RoomHit side = sensor.cast(direction.normalized() + sign * footprint, origin);
    if (std::abs(rangeOf(side) - rangeOf(centre)) > std::abs(rangeOf(other) - rangeOf(centre))) other = side;
  }
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  if (other.label == SurfaceLabel::kNone || centre.label == SurfaceLabel::kNone || std::abs(other.range - centre.range) < 0.1 ||
      unit(*rng) < 0.5) {
    return centre;
  }
  const double mixed = centre.range + unit(*rng) * (other.range - centre.range);
  if (std::abs(mixed - centre.range) > 0.02) centre.label = SurfaceLabel::kMixed;
  centre.range = mixed;
  return centre;
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

SimulatedRoomView boardHeldInFurnishedRoom(const SimulatedSensor& sensor, const TargetDescription& target) {
  SimulatedRoomView view;
  view.sensor = &sensor;
  view.target = &target;
  view.layout = RoomLayout::kFurnished;
  view.person_holds_target = true;
  view.mixed_pixels = true;
  view.reference_from_target.translation() = Eigen::Vector3d(2.0, 0.0, 1.1);
  view.reference_from_target.linear() = targetFacingRig();
  return view;
}

std::vector<float> simulateLaserRanges(const SimulatedRoomView& view, std::mt19937* rng, SimulatedTruth* truth) {
  const SensorInRoom sensor(view);
  constexpr int kBeams = 1081;
  constexpr double kStep = 0.25 * M_PI / 180.0;
  const auto rayAt = [](double azimuth) { return Eigen::Vector3d(std::cos(azimuth), std::sin(azimuth), 0.0); };
  std::vector<RoomHit> hits;
  std::vector<double> noise;  // drawn beam by beam after each beam's return, as the generator's sequence was before wide beams
  for (int beam = 0; beam < kBeams; ++beam) {
    const double azimuth = -135.0 * M_PI / 180.0 + kStep * beam;
    const Eigen::Vector3d ray = rayAt(azimuth);
    const double footprint = 0.1 * M_PI / 180.0;
    hits.push_back(rangeReturn(sensor, view, ray, footprint * Eigen::Vector3d(-ray.y(), ray.x(), 0.0), rng));
    noise.push_back(hits.back().label == SurfaceLabel::kNone ? 0.0 : noisy(0.0, view.range_noise, rng));
  }
  if (view.beam_aperture > 0.0 || view.beam_divergence > 0.0) {
    // A beam as wide as a disc, partly on a surface nearer than its centre's (by kNearerSurface or more:
    // the board before the room behind it), returns from it: from that surface's part nearest the
    // centre (the ring nearest it, within half the beam's width at that surface's range), sampled on 24
    // rings of 16 across its widest cone (at 0.2 m), for the beams whose cone can reach the board (its
    // corners' bearings and elevations). A beam wholly on one surface returns its centre's range (the
    // footprint's middle).
    const auto halfWidth = [&](double range) { return 0.5 * view.beam_aperture / std::max(range, 0.05) + 0.5 * view.beam_divergence; };
    const double widest = halfWidth(0.2);
    const Eigen::Isometry3d sensor_from_target = view.sensor->reference_from_sensor.inverse() * view.reference_from_target;
    double low = M_PI, high = -M_PI, below = M_PI / 2, above = -M_PI / 2;
    for (const double sx : {-0.5, 0.5})
      for (const double sy : {-0.5, 0.5}) {
        const Eigen::Vector3d c = sensor_from_target * Eigen::Vector3d(sx * view.target->width, sy * view.target->height, 0.0);
        low = std::min(low, std::atan2(c.y(), c.x())), high = std::max(high, std::atan2(c.y(), c.x()));
        const double elevation = std::atan2(c.z(), c.head<2>().norm());
        below = std::min(below, elevation), above = std::max(above, elevation);
      }
    const bool reaches = below - widest <= 0.0 && above + widest >= 0.0 && high - low < M_PI;  // a board behind: none
    for (int beam = 0; beam < kBeams && reaches; ++beam) {
      const double azimuth = -135.0 * M_PI / 180.0 + kStep * beam;
      if (azimuth < low - widest || azimuth > high + widest) continue;
      const Eigen::Vector3d ray = rayAt(azimuth), side(-ray.y(), ray.x(), 0.0), up = Eigen::Vector3d::UnitZ();
      const RoomHit centre = hits[beam];
      for (int ring = 1; ring <= 24 && hits[beam].range == centre.range; ++ring)
        for (int k = 0; k < 16; ++k) {
          const double radius = widest * ring / 24.0, angle = 2.0 * M_PI * k / 16.0;
          const RoomHit hit = sensor.cast(ray + radius * (std::cos(angle) * side + std::sin(angle) * up));
          if (hit.label != SurfaceLabel::kNone && radius <= halfWidth(hit.range) && hit.range < rangeOf(centre) - kNearerSurface &&
              hit.range < rangeOf(hits[beam])) {
            hits[beam] = hit;
          }
        }
      if (centre.label == SurfaceLabel::kNone && hits[beam].label != SurfaceLabel::kNone) noise[beam] = noisy(0.0, view.range_noise, rng);
    }
  }
  std::vector<float> ranges;
  if (truth) *truth = {};
  for (int beam = 0; beam < kBeams; ++beam) {
    const RoomHit& hit = hits[beam];
    ranges.push_back(hit.label == SurfaceLabel::kNone ? std::numeric_limits<float>::infinity() : static_cast<float>(hit.range + noise[beam]));
    if (truth) truth->labels.push_back(hit.label);
  }
  return ranges;
}

const std::vector<double> kVlp16VerticalOffsets = {0.0112, 0.0097, 0.0081, 0.0066, 0.0051, 0.0037, 0.0022, 0.0007,
                                                   -0.0007, -0.0022, -0.0037, -0.0051, -0.0066, -0.0081, -0.0097, -0.0112};

LidarModel parseLidarModel(const std::string& name, const std::string& what) {
  if (name == "vlp16") return LidarModel::kVlp16;
  if (name == "ouster64") return LidarModel::kOuster64;
  if (name == "livox") return LidarModel::kLivox;
  if (name == "scanner") return LidarModel::kScanner;
  throw InputError(what + ": '" + name + "' is unknown: expected vlp16, ouster64, livox or scanner");
}

std::vector<Eigen::Vector3d> simulateLidarCloud(const SimulatedRoomView& view, std::mt19937* rng, SimulatedTruth* truth) {
  const SensorInRoom sensor(view);
  std::vector<Eigen::Vector3d> points;
  if (truth) *truth = {};
  const auto cast = [&](const Eigen::Vector3d& ray, const Eigen::Vector3d& footprint, int ring, double bias) {
    const Eigen::Vector3d origin(0.0, 0.0, ring >= 0 && ring < static_cast<int>(view.ring_height.size()) ? view.ring_height[ring] : 0.0);
    const RoomHit hit = rangeReturn(sensor, view, ray, footprint, rng, origin);
    const bool dark = hit.label == SurfaceLabel::kTarget && boardGrey(view.target->pattern, hit.on_target) < 128.0;
    if (hit.label == SurfaceLabel::kNone || (dark && view.dark_absorbs)) {
      if (!view.no_returns_at_origin || ring < 0) return;
      points.push_back(Eigen::Vector3d::Zero());
      if (truth) truth->labels.push_back(SurfaceLabel::kNone), truth->rings.push_back(ring);
      return;
    }
    points.push_back(origin + (noisy(hit.range, view.range_noise, rng) + bias + (dark ? view.dark_range_offset : 0.0)) * ray);
    if (truth) truth->labels.push_back(hit.label), truth->rings.push_back(ring);
  };
  if (view.lidar_model == LidarModel::kLivox) {
    // A rosette: the beam swings out from the axis and back (250 Hz) while the swing turns (sqrt(2) x 37 Hz),
    // 100,000 points a second; a frame is 0.1 s of it from view.time on.
    constexpr double kHalfAngle = 35.0 * M_PI / 180.0;
    for (int i = 0; i < 10000; ++i) {
      const double t = view.time + i * 1e-5;
      const double off_axis = kHalfAngle * std::sin(2 * M_PI * 250.0 * t), around = 2 * M_PI * 37.0 * std::sqrt(2.0) * t;
      const Eigen::Vector3d ray(std::cos(off_axis), std::sin(off_axis) * std::cos(around), std::sin(off_axis) * std::sin(around));
      cast(ray, 0.0015 * ray.unitOrthogonal(), -1, 0.0);
    }
    return points;
  }
  const bool ouster = view.lidar_model == LidarModel::kOuster64, scanner = view.lidar_model == LidarModel::kScanner;
  const int rings = ouster ? 64 : scanner ? 77 : 16, steps = ouster ? 1024 : scanner ? 800 : 1800;
  const double lowest = ouster ? -16.6 : scanner ? -19.0 : -15.0, ring_step = ouster ? 33.2 / 63 : scanner ? 0.5 : 2.0;
  // A spinning head's steps go all round; a scanner's over 120 degrees ahead.
  const double sweep = scanner ? 2.0 * M_PI / 3.0 : 2 * M_PI;
  for (int ring = 0; ring < rings; ++ring) {
    const double elevation = (lowest + ring_step * ring) * M_PI / 180.0;
    const double bias = ring < static_cast<int>(view.ring_bias.size()) ? view.ring_bias[ring] : 0.0;
    for (int step = 0; step < steps; ++step) {
      const double azimuth = step * sweep / steps - 0.5 * sweep;
      const Eigen::Vector3d ray(std::cos(elevation) * std::cos(azimuth), std::cos(elevation) * std::sin(azimuth), std::sin(elevation));
      // A beam's footprint is about 3 mrad wide.
      cast(ray, 0.0015 * Eigen::Vector3d(-std::sin(azimuth), std::cos(azimuth), 0.0), ring, bias);
    }
  }
  return points;
}

DepthImage simulateDepthImage(const SimulatedRoomView& view, const PinholeCamera& camera, std::mt19937* rng, SimulatedTruth* truth) {
  const SensorInRoom sensor(view);
  DepthImage depth(camera.width, camera.height, 0.0f);
  if (truth) *truth = {}, truth->labels.assign(static_cast<std::size_t>(camera.width) * camera.height, SurfaceLabel::kNone);
  for (int v = 0; v < camera.height; ++v) {
    for (int u = 0; u < camera.width; ++u) {
      const Eigen::Vector3d ray((u - camera.cx) / camera.fx, (v - camera.cy) / camera.fy, 1.0);
      // The footprint: half a pixel either side.
      const RoomHit hit = rangeReturn(sensor, view, ray, Eigen::Vector3d(0.5 / camera.fx, 0.0, 0.0) / ray.norm(), rng);
      if (hit.label == SurfaceLabel::kNone) continue;
      // Range noise along the ray, stored as depth (z).
      depth(u, v) = static_cast<float>(noisy(hit.range, view.range_noise, rng) / ray.norm());
      if (truth) truth->labels[static_cast<std::size_t>(v) * camera.width + u] = hit.label;
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
  const SensorInRoom sensor(view);
  const PinholeCamera& camera = rays.camera();
  ColorImage image(camera.width, camera.height);
  std::normal_distribution<double> noise(0.0, std::max(noise_levels, 1e-12));
  for (int v = 0; v < camera.height; ++v) {
    for (int u = 0; u < camera.width; ++u) {
      double grey = 0.0;
      for (int sample = 0; sample < 4; ++sample) {
        const RoomHit hit = sensor.cast(rays.ray(u, v, sample));
        grey += 0.25 * (hit.label == SurfaceLabel::kTarget ? boardGrey(view.target->pattern, hit.on_target)
                        : hit.label == SurfaceLabel::kNone   ? 60.0
                        : hit.label == SurfaceLabel::kPerson ? 90.0
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
