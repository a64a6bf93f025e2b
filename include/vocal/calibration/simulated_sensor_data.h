#pragma once
// What each sensor's driver would publish while the target is moved through a room: full range scans
// of a lidar or 2D laser, depth images of an RGB-D sensor and images of a camera, with the target,
// the floor (z = 0 of the rig frame) and a wall (x = 4.5 m) in view. The input of end-to-end tests
// and demos of the calibration session (extraction, association, calibration) with known extrinsics.

#include <random>
#include <vector>

#include <Eigen/Geometry>

#include "vocal/calibration/rig_description.h"
#include "vocal/calibration/rig_simulator.h"
#include "vocal/core/image.h"
#include "vocal/core/lens_distortion.h"
#include "vocal/core/pinhole_camera.h"

namespace vocal {

struct SimulatedRoomView {
  const SimulatedSensor* sensor = nullptr;
  Eigen::Isometry3d reference_from_target = Eigen::Isometry3d::Identity();
  const TargetDescription* target = nullptr;
  double range_noise = 0.0;  // metres along each ray
};

// A 2D laser's ranges in beam order (270 degrees, 0.25 degree steps from -135 degrees; infinity where
// nothing is hit within 8 m) or a 16-ring lidar's points (its hits only).
std::vector<float> simulateLaserRanges(const SimulatedRoomView& view, std::mt19937* rng);
std::vector<Eigen::Vector3d> simulateLidarCloud(const SimulatedRoomView& view, std::mt19937* rng);
// Depth in metres (0 where nothing is hit) of an RGB-D sensor with the given intrinsics.
DepthImage simulateDepthImage(const SimulatedRoomView& view, const PinholeCamera& camera, std::mt19937* rng);
// The viewing ray (z = 1) of each 2x2 subsample of every pixel of a camera through its lens: computed
// once per camera, as undistorting is most of the cost of rendering a distorted image.
class CameraRays {
 public:
  CameraRays(const PinholeCamera& camera, const LensDistortion& distortion);
  const PinholeCamera& camera() const { return camera_; }
  const Eigen::Vector3d& ray(int u, int v, int subsample) const {
    return rays_[(static_cast<std::size_t>(v) * camera_.width + u) * 4 + subsample];
  }

 private:
  PinholeCamera camera_;
  std::vector<Eigen::Vector3d> rays_;
};

// A camera's image: the checkerboard (black and white squares on the white board), grey room,
// 2x2 supersampled, with Gaussian pixel noise of `noise_levels` grey levels, through the lens the rays
// were made for.
ColorImage simulateCameraImage(const SimulatedRoomView& view, const CameraRays& rays, double noise_levels,
                               std::mt19937* rng);
// The same for one image (the rays made here).
ColorImage simulateCameraImage(const SimulatedRoomView& view, const PinholeCamera& camera, double noise_levels,
                               std::mt19937* rng, const LensDistortion& distortion = {});

}  // namespace vocal
