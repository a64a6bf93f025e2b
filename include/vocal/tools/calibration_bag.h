#pragma once
// Calibration sessions as rosbags: a simulated session written with the topics of a rig description
// (the demo and the end-to-end test), and any recorded session read back into a CalibrationSession.

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "vocal/calibration/calibration_session.h"
#include "vocal/calibration/rig_description.h"
#include "vocal/core/lens_distortion.h"
#include "vocal/simulation/rig_simulator.h"
#include "vocal/simulation/simulated_pan_tilt.h"
#include "vocal/simulation/simulated_room.h"
#include "vocal/simulation/simulated_sensor_data.h"

namespace vocal {

// The rig description of simulated sensors: topics /<name>/..., every sensor's true pose when
// `with_all_poses` (ground truth), else the first sensor's only (what a user knows).
RigDescription describeSimulatedRig(const std::vector<SimulatedSensor>& sensors, const TargetDescription& target,
                                    bool with_all_poses);

// A fault of one sensor in a simulated session; the ground truth stays its mount as described.
struct SimulatedSensorFault {
  enum class Kind {
    kMoves,       // on a joint the rig does not describe: turned by up to `amount` rad (a pan-tilt head, its pivot
                  // 8 cm behind the sensor) to a new place at each still pose
    kBumped,      // moved once, half way through the session: `amount` metres and `amount` rad
    kTimeOffset,  // its stamps `amount` seconds late (a clock not synchronised)
    kFocalScale,  // a camera's camera_info gives its focal length times `amount` (wrong intrinsics)
  };
  Kind kind = Kind::kMoves;
  int sensor = 0;
  double amount = 0.0;
};
// "moves:SENSOR:RAD", "bumped:SENSOR:AMOUNT", "time-offset:SENSOR:S", "focal:SENSOR:SCALE" with a sensor
// named in `sensors`; throws InputError naming `what` otherwise.
SimulatedSensorFault parseSimulatedSensorFault(const std::string& text, const std::vector<SimulatedSensor>& sensors, const std::string& what);
// Where sensor `sensor_index`, built at `as_built` (in any frame), sits at still pose k of `poses` with
// `faults` (kMoves turns it about a pivot behind it, kBumped moves it from the session's half way on;
// the other kinds leave it where it was built).
Eigen::Isometry3d faultyPlacement(const Eigen::Isometry3d& as_built, const std::vector<SimulatedSensorFault>& faults, int sensor_index,
                                  int k, int poses, std::uint32_t seed);

struct SimulatedSessionOptions {
  int target_poses = 12;
  double turn_range = -1.0;  // radians the target turns left / right at most (< 0: as far as it tilts)
  double still_seconds = 0.6;   // the target held still at each pose
  double moving_seconds = 0.4;  // ... then carried to the next
  double rate = 10.0;           // Hz, every sensor's unless given below
  // Hz per sensor type (0: rate): a rig's sensors rarely share one (a 30 Hz camera, a 10 Hz lidar, a
  // triggered 3 Hz laser).
  double camera_rate = 0.0, rgbd_rate = 0.0, lidar_rate = 0.0, laser_rate = 0.0;
  double range_noise = 0.001;  // metres, every range sensor's unless given below
  double image_noise = 2.0;  // grey levels
  // The room and what real range sensors add (simulated_room.h, simulated_sensor_data.h).
  RoomLayout room = RoomLayout::kPlain;
  bool person_holds_target = false;
  double lidar_noise = -1.0;  // metres; < 0: range_noise
  double laser_noise = -1.0;  // a 2D laser's, metres; < 0: range_noise
  double laser_beam_aperture = 0.0, laser_beam_divergence = 0.0;  // a 2D laser's beam across (SimulatedRoomView)
  double ring_bias = 0.0;     // metres: each lidar ring's bias drawn uniformly from +-this
  double lidar_range_offset = 0.0;  // metres added to every ring's ranges (a range offset the rings share)
  LidarModel lidar_model = LidarModel::kVlp16;
  bool lidar_vertical_offsets = false;  // a VLP-16's lasers at their own heights (kVlp16VerticalOffsets)
  double dark_range_offset = 0.0;       // metres a lidar return reads too long on the board's dark squares
  bool mixed_pixels = false;
  // Camera i's lens is camera_lenses[i % size] (none when empty): images rendered through it,
  // camera_info carries it.
  std::vector<LensDistortion> camera_lenses;
  // Faults of real sessions, each on one sensor (bench/calibration_faults.py): what MSG-Cal must flag.
  std::vector<SimulatedSensorFault> faults;
  bool dark_absorbs = false;  // lidar beams on the board's dark squares return nothing (low reflectivity)
  bool board_on_stand = false;  // the board on a stand (two posts, feet), carried with it, instead of held
  // Metres: each lidar cloud cropped to the returns within this of a still pose's board centre (a driver
  // or filter that keeps only the region where the board was; 0: the whole scan).
  double lidar_crop = 0.0;
  // Sensors on a pan-tilt head (simulated_pan_tilt.h): each of head_sensors sits on its tilt link at its
  // reference_from_sensor (its mount there), the head's joints on joint_states_topic at joint_state_rate.
  std::optional<SimulatedPanTilt> head;
  std::vector<int> head_sensors;
  std::string joint_states_topic = "/joint_states";
  double joint_state_rate = 200.0;
  int depth_width = 320;     // RGB-D depth images (camera images are 640x480)
  int depth_height = 240;
  std::uint32_t seed = 1;
};

struct SimulatedSessionSummary {
  std::size_t messages = 0;
  std::vector<Eigen::Isometry3d> reference_from_target;  // the still poses
};

// A pan-tilt session's rig (simulate_calibration_session --pan-tilt): the example rig's lidar (the
// reference) and 2D laser, and an RGB-D camera (head_camera, the last) whose pose is its mount on the
// head's tilt link (looking along the link's x, 6 cm ahead of the tilt axis). `head_laser`: the 2D laser
// (head_laser) on the tilt link too, 5 cm under the camera, scanning across its line of sight.
std::vector<SimulatedSensor> panTiltRig(bool head_laser = false);
// Puts the last of `sensors` (panTiltRig), and the 2D laser where `head_laser`, on a pan-tilt head aimed
// (the camera) at each still pose of `options` (sets its head and head_sensors), and names the head's joints
// in `rig` (offsets unknown: 0; the camera's mount given as known when `pose_known`) and in `truth` (their
// true offsets, the mounts); the tilt joint's true origin `tilt_origin_error` (metres, in the pan link) from
// the one `rig` gives (a head built off its model).
void putOnPanTiltHead(const std::vector<SimulatedSensor>& sensors, SimulatedSessionOptions* options, RigDescription* rig,
                      RigDescription* truth, bool pose_known, const Eigen::Vector3d& tilt_origin_error = Eigen::Vector3d::Zero(),
                      bool head_laser = false);

// The board's still poses of a session (rig frame): the rig simulator's spread tilts facing the rig.
std::vector<Eigen::Isometry3d> simulatedStillPoses(const SimulatedSessionOptions& options, const TargetDescription& target);

// Each sensor publishes at its own rate and phase, unsynchronised, while the target follows one
// timeline (still, then carried, per pose). Throws InputError naming the bag when it cannot be written,
// and for a rate or still time that is not positive.
SimulatedSessionSummary writeSimulatedCalibrationBag(const std::vector<SimulatedSensor>& sensors, const RigDescription& rig,
                                                     const SimulatedSessionOptions& options, const std::string& bag_path);

struct BagReadSummary {
  std::size_t messages = 0;  // on the rig's topics
  std::vector<std::string> problems;  // per dropped message: topic, stamp and why (first 20)
  std::size_t dropped = 0;
};

// Feeds every message on the rig's topics to `session` in bag order (camera_info before its images
// or depth is required; the latest one is used). A message that cannot be used is dropped and
// reported, not fatal. Throws InputError naming the bag when it cannot be read or holds none of the
// rig's topics. The target is searched in up to `threads` messages at once (0: OMP_NUM_THREADS where
// set, else the cores this process may use; 1: each in turn on the reading thread); the session takes
// every result in bag order, so the outcome is the same with any number.
BagReadSummary readCalibrationBag(const std::string& bag_path, CalibrationSession* session,
                                  const std::function<void(std::size_t)>& progress = nullptr, int threads = 0);

struct CameraImageRequest {
  int sensor = 0;      // a camera of the rig
  double stamp = 0.0;  // seconds
};
struct CameraImage {
  bool found = false;  // false: no image on the camera's topic, or no usable camera_info
  double stamp = 0.0;
  ColorImage image;
  PinholeCamera camera;  // from the camera's first usable camera_info
  LensDistortion lens;
};

// Per request, the camera's image stamped nearest the request (the overlays read images again after
// calibrating rather than keep a session's images). Throws InputError naming the bag when it cannot be
// read, and for an image that does not convert.
std::vector<CameraImage> readCameraImagesNear(const std::string& bag_path, const RigDescription& rig,
                                             const std::vector<CameraImageRequest>& requests);

}  // namespace vocal
