#pragma once
// The rig description YAML of the design: the contract between a user, the calibration tool and the
// MsgCalibration nodelet. Which sensors, of which type, on which topics, the target, and the pose of
// the reference sensor (optional initial guesses for the others).
//
//   reference_frame: base_link
//   target: {type: checkerboard, rows: 6, cols: 8, square_size: 0.06, width: 0.9, height: 0.7}
//   sensors:
//     - {name: kinect, type: rgbd, frame_id: camera_rgb_optical_frame, depth_topic: ...,
//        camera_info_topic: ..., pose: [x, y, z, qx, qy, qz, qw]}
//     - {name: lidar, type: lidar3d, frame_id: velodyne, cloud_topic: /velodyne_points,
//        crop_box: [0, -2, -1, 4, 2, 1]}   # optional, range sensors: search only inside (sensor frame)
//     - {name: scan, type: laser2d, frame_id: laser, scan_topic: /scan}
//     - {name: cam2, type: camera, frame_id: cam2_optical, image_topic: ..., camera_info_topic: ...}
//
// A camera on a robot arm (hand-eye): its `parent` is the arm's tool frame, a frame that moves, whose pose
// in reference_frame comes from tf; the board is then fixed (target `parent: <reference_frame>`). Or the
// board on the tool (target `parent: <tool frame>`) and the camera fixed in reference_frame:
//
//   reference_frame: panda_link0
//   target: {type: checkerboard, rows: 6, cols: 9, square_size: 0.0236, width: 0.3, height: 0.2, parent: panda_link0}
//   sensors:
//     - {name: wrist_camera, type: camera, frame_id: camera_color_optical_frame, parent: panda_EE, image_topic: ...}
//
// A sensor behind a robot's joints (a camera on a pan-tilt head): its `parent` is a link of the joints
// the rig names, in a `joints:` list or a URDF (`urdf: robot.urdf`, relative to the YAML's folder; live,
// `urdf_param: /robot_description`, the parameter robot_state_publisher reads), and
// their positions come from sensor_msgs/JointState on `joint_states_topic` (/joint_states). Each joint's
// zero offset is calibrated; the sensor's mount in its link too, unless `pose_known: true` holds its
// `pose` (there: in its parent link):
//
//   joints:
//     - {name: head_pan_joint, type: revolute, parent: base_link, child: head_pan_link, origin: [x, y, z, qx, qy, qz, qw], axis: [0, 0, 1]}
//     - {name: head_tilt_joint, type: revolute, parent: head_pan_link, child: head_tilt_link, origin: [...], axis: [0, 1, 0]}
//   sensors:
//     - {name: head_camera, type: rgbd, frame_id: head_camera_optical_frame, parent: head_tilt_link, depth_topic: ...}
//
// An IMU (camera_imu_calibration.h) is calibrated against a camera of the rig from a session where the rig
// was waved before the fixed board: every frame of `camera` (default: the rig's first camera) with the
// board in view and the IMU's sensor_msgs/Imu on `imu_topic`. Its noise figures take Kalibr's imu.yaml
// names (continuous time; consumer MEMS defaults). With a `pose` it is the rig's reference: calibrated
// first, its camera placed through it is the reference of the still poses:
//
//     - {name: imu, type: imu, frame_id: imu_link, imu_topic: /imu, camera: cam0,
//        gyroscope_noise_density: 2.4e-4, gyroscope_random_walk: 2.0e-5,
//        accelerometer_noise_density: 2.0e-3, accelerometer_random_walk: 3.0e-4}

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "vocal/calibration/calibration_types.h"
#include "vocal/calibration/extraction/pattern_observation.h"
#include "vocal/calibration/extraction/target_extraction.h"
#include "vocal/calibration/joint_chain.h"
#include "vocal/core/imu_samples.h"

namespace vocal {

struct TargetDescription {
  TargetPattern pattern;  // rows / cols count inner corners
  // Metres: the whole board, what range sensors see. A rig of cameras alone may leave both out: the
  // pattern's squares then.
  double width = 0.9;
  double height = 0.7;
  // Empty: moved by hand, a new pose per still period. reference_frame: fixed there, one unknown pose
  // for the whole session. Another frame: held by it (a board in an arm's gripper, its pose from tf).
  std::string parent;
};

struct RigSensorDescription {
  SensorSpec spec;
  std::string image_topic, camera_info_topic, depth_topic, cloud_topic, scan_topic;
  std::optional<Eigen::Isometry3d> pose;  // in reference_frame
  std::optional<CropBox> crop_box;        // range sensors: where the target is searched
  // A frame that moves (an arm's tool) that the sensor is mounted on, its pose in reference_frame from
  // tf, or a link behind the rig's joints; empty: mounted rigidly in reference_frame (a `parent` naming
  // reference_frame reads as empty).
  std::string parent;
  bool pose_known = false;  // behind joints: `pose` is its mount in `parent`, known (held)
};

// An IMU of the rig: not one of its plane-seeing sensors, so kept apart from them (RigDescription::imus).
struct RigImuDescription {
  std::string name, frame_id, imu_topic;
  int camera = -1;  // the camera sensor it is calibrated against (index into RigDescription::sensors)
  ImuNoise noise;
  std::optional<Eigen::Isometry3d> pose;  // in reference_frame: the rig's reference
};

// Where an arm moves a camera or the board (RigDescription::handEye), in the rig's terms.
struct HandEyeRig {
  int camera = -1;         // the main camera: the first on the other side from the board (-1: none)
  bool eye_in_hand = true; // the board fixed in the reference frame (else on the tool)
  std::string tool_frame;  // the frame that moves, looked up in tf ...
  // ... or a link of the rig's joints (an arm whose joints the rig names): its pose from the joint states
  // through `chain` (jointChain from the reference frame), the joints' offsets calibrated with the rest.
  bool from_joints = false;
  std::vector<int> chain;
  // Per sensor: on a link of the joints other than the tool (a forearm camera, a head's camera), the
  // joints from the reference frame to it; empty for the others (HandEyeSensor::link_chain).
  std::vector<std::vector<int>> link_chains;
  // The joints each still pose reads: the tool's chain, then the links' (ArmJoints::read).
  std::vector<int> readJoints() const { return jointsOfChains(chain, link_chains); }
};

struct RigDescription {
  std::string reference_frame = "base_link";
  TargetDescription target;
  std::vector<RigSensorDescription> sensors;
  int reference_sensor = 0;  // the first sensor with a pose (-1 for a hand-eye rig: the base frame is the reference)
  // The robot's joints (a `joints:` list, or those of `urdf`), and where their positions arrive.
  std::vector<JointDescription> joints;
  std::string urdf;  // the file they were read from (as given), empty for a list
  std::string urdf_path;  // ... and where it is (relative to the rig YAML's folder)
  // Or the parameter that holds the URDF (robot_description, live): readRigDescription leaves the joints
  // empty and the rig unfinished; the reader of the parameter gives them with setRigJoints.
  std::string urdf_param;
  std::string joint_states_topic = "/joint_states";
  // Joints whose origin is an unknown too (`free_joint_origins: [NAME, ...]`; robot_calibration's free
  // frames): an arm whose link lengths or angles are off its model. finishRig marks them free_origin.
  std::vector<std::string> free_joint_origins;
  std::vector<RigImuDescription> imus;
  // The IMU whose `pose` makes it the reference (its camera then has none), or -1.
  int reference_imu = -1;

  std::vector<SensorSpec> specs() const;
  // Set when a sensor or the board is on a frame that moves (tf's, not a link of `joints`).
  std::optional<HandEyeRig> handEye() const;
  // Whether the sensor sits behind joints (its parent is a link of `joints`), and whether a frame is such a link.
  bool behindJoints(int sensor) const;
  bool isJointLink(const std::string& frame) const;
  // Whether the session needs the joints' states: a sensor behind joints, or an arm's tool from them.
  bool needsJointStates() const;
  // Each sensor's chain from reference_frame (jointChain) and known mounts, for the graph: only the joints
  // a sensor is behind (CalibrationOptions::mounts). Empty chains when no sensor is behind joints.
  JointedMounts jointedMounts() const;
};

// Throws InputError starting with `where` for a pattern under 2 x 2 inner corners, a square size or board
// side that is not positive, or a pattern whose squares do not fit on the board (its columns run along
// the width).
void checkTargetDescription(const TargetDescription& target, const std::string& where);

// Throws InputError naming the file and the key: unknown or missing keys, a sensor type without the
// topics it needs (camera: image + camera_info; rgbd: depth + camera_info; lidar3d: cloud; laser2d:
// scan), a malformed crop_box or one on a camera, duplicate names, no sensor with a pose, a reference that is a 2D laser, a bad target;
// and for the moving frames of a hand-eye rig (RigDescription::handEye): two moving frames, a camera on
// the tool over a board moved by hand, a range sensor on the board's side, a 2D laser, no camera on the
// other side from the board; for joints: a joint with a missing or malformed key, an unknown type, a zero
// axis, a name or child used twice, a URDF that cannot be read, a sensor's parent no joint chain reaches
// from reference_frame, `pose_known` without a pose or on a rigid sensor, joints in a hand-eye rig; for an
// IMU: no imu_topic, a `camera` that is no camera of the rig (or no camera at all), a negative noise figure,
// an IMU in a rig with joints or an arm, an IMU with a pose beside another fixed sensor with one.
// `free_joint_origins` naming no joint of the rig.
RigDescription readRigDescription(const std::string& path);

// A rig read with `urdf_param`: its joints (urdfJointsFromString of the parameter), then what depends on
// them checked as readRigDescription does, `where` naming the rig. Throws InputError as it does.
void setRigJoints(RigDescription* rig, std::vector<JointDescription> joints, const std::string& where);

// Writes what readRigDescription reads (every sensor with a pose writes it). Throws InputError naming
// the file when it cannot be written.
void writeRigDescription(const std::string& path, const RigDescription& rig);

}  // namespace vocal
