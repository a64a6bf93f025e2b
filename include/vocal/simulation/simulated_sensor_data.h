#pragma once
// What each sensor's driver would publish while the target is moved through a room: full range scans
// of a lidar or 2D laser, depth images of an RGB-D sensor and images of a camera, of the target in a
// plain or furnished room (simulated_room.h), with what real range sensors add: noise along the ray,
// a range bias per lidar ring, mixed pixels where a beam's footprint straddles an edge. The input of
// end-to-end tests and demos of the calibration session (extraction, association, calibration) with
// known extrinsics; the range sensors also say what each point hit, the truth extraction is counted on.

#include <random>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "vocal/calibration/rig_description.h"
#include "vocal/core/image.h"
#include "vocal/core/lens_distortion.h"
#include "vocal/core/pinhole_camera.h"
#include "vocal/simulation/rig_simulator.h"
#include "vocal/simulation/simulated_room.h"

namespace vocal {

// The lidars simulated: spinning ones with rings (a VLP-16: 16 rings 2 degrees apart from -15, 0.2 degree
// azimuth steps; an Ouster OS1-64: 64 rings over +-16.6 degrees, 1024 azimuth steps) and a solid-state
// one with a non-repeating pattern (Livox-like: a rosette over a 70-degree cone about its x axis, 10,000
// points per 0.1 s frame, denser in the middle, never the same twice: no rings), and a scanning 3D laser
// (a mirror or nodding head: 77 elevation bands 0.5 degrees apart over +-19 degrees, 0.15-degree steps
// over 120 degrees ahead, and a driver that publishes no ring field).
enum class LidarModel { kVlp16, kOuster64, kLivox, kScanner };
// "vlp16", "ouster64", "livox", "scanner"; throws InputError naming `what` for anything else.
LidarModel parseLidarModel(const std::string& name, const std::string& what);

struct SimulatedRoomView {
  const SimulatedSensor* sensor = nullptr;
  Eigen::Isometry3d reference_from_target = Eigen::Isometry3d::Identity();
  const TargetDescription* target = nullptr;
  double range_noise = 0.0;  // metres along each ray
  RoomLayout layout = RoomLayout::kPlain;
  bool person_holds_target = false;  // furnished rooms only
  bool board_on_stand = false;       // the target on two posts with feet (SimulatedRoom)
  std::vector<double> ring_bias;     // metres added to each lidar ring's ranges (none when empty)
  // Where a beam's footprint straddles a range edge, half the returns lie between the two surfaces
  // (what lidars and time-of-flight depth cameras do at a board's edges).
  bool mixed_pixels = false;
  // A 2D laser's beam across: its width at the exit (metres) and its divergence (radians), a SICK LMS1xx's
  // 8 mm and 15 mrad by its manual. A beam with any of its width on a nearer surface returns that surface
  // (the board's edge seen beyond it by half the beam's width); zero: a beam as thin as a ray.
  double beam_aperture = 0.0, beam_divergence = 0.0;
  LidarModel lidar_model = LidarModel::kVlp16;
  double time = 0.0;  // seconds into the session: where a non-repeating pattern has got to
  // Metres each lidar ring's laser sits above the lidar's origin (a VLP-16's lasers are up to 11 mm
  // apart, kVlp16VerticalOffsets): its rays start there, and its points' elevation seen from the origin
  // drifts with range - what clustering elevations into rings stumbles on, and a driver's ring field not.
  std::vector<double> ring_height;
  // Metres a lidar return reads too long on the board's dark squares (low reflectivity: a real lidar's
  // range depends on the return's intensity).
  double dark_range_offset = 0.0;
  bool dark_absorbs = false;  // a lidar's returns on the board's dark squares are lost (too little light back)
  // A spinning lidar's ray without a return is a point at the origin (an Ouster driver's organised cloud),
  // not left out (a Velodyne driver's unorganised one).
  bool no_returns_at_origin = false;
};

// A VLP-16's per-laser vertical offsets (its manual's vert_correction), metres, by ascending elevation.
extern const std::vector<double> kVlp16VerticalOffsets;

// The board held still by a person 2 m in front of the rig, facing it, in the furnished room, mixed
// pixels on (noise and ring biases are the caller's): one messy view for tests and benchmarks.
SimulatedRoomView boardHeldInFurnishedRoom(const SimulatedSensor& sensor, const TargetDescription& target);

// What each ray hit (laser: per beam, kNone where nothing; lidar: per returned point; depth: per pixel), and a lidar point's ring.
struct SimulatedTruth {
  std::vector<SurfaceLabel> labels;
  std::vector<int> rings;
};

// A 2D laser's ranges in beam order (270 degrees, 0.25 degree steps from -135 degrees; infinity where
// nothing is hit within 8 m) or a lidar's points (view.lidar_model; its hits only - with
// view.no_returns_at_origin every ray, a miss at the origin -, a spinning lidar's ring per point in
// `truth` (a scanner's elevation band), -1 for a pattern without rings).
std::vector<float> simulateLaserRanges(const SimulatedRoomView& view, std::mt19937* rng, SimulatedTruth* truth = nullptr);
std::vector<Eigen::Vector3d> simulateLidarCloud(const SimulatedRoomView& view, std::mt19937* rng, SimulatedTruth* truth = nullptr);
// Depth in metres (0 where nothing is hit) of an RGB-D sensor with the given intrinsics.
DepthImage simulateDepthImage(const SimulatedRoomView& view, const PinholeCamera& camera, std::mt19937* rng,
                              SimulatedTruth* truth = nullptr);
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
