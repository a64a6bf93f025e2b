#include "vocal/tools/hand_eye_bag.h"

#include <sensor_msgs/JointState.h>

#include <cmath>
#include <fstream>
#include <random>

#include <opencv2/imgcodecs.hpp>
#include <rosbag/bag.h>
#include <sensor_msgs/CompressedImage.h>
#include <tf2_msgs/TFMessage.h>

#include "vocal/core/errors.h"
#include "vocal/core/se3.h"
#include "vocal/nodelets/message_conversions.h"
#include "vocal/simulation/simulated_sensor_data.h"
#include "vocal/tools/bag_file.h"

namespace vocal {

namespace {
const char kBase[] = "arm_base";
const char kFlange[] = "arm_flange";
const char kTool[] = "arm_tool";
const char kForearm[] = "forearm_link";  // simulated_joint_arm.h's link after its first three joints
const char* const kHead = SimulatedJointArm::kHeadLink;
// The tool 10 cm past the flange (a gripper or an adapter plate), on /tf_static.
Eigen::Isometry3d flangeFromTool() {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(0.0, 0.0, 0.1);
  return pose;
}
// A sensor of the rig in its parent: the camera's (on the tool, or fixed; on the forearm), the fixed
// others' by type.
Eigen::Isometry3d sensorPoseInParent(const SimulatedArm& arm, const RigSensorDescription& sensor) {
  if (sensor.parent == kForearm) return arm.forearm_camera;
  if (sensor.parent == kHead) return arm.head_camera;
  switch (sensor.spec.type) {
    case SensorType::kLidar3d: return arm.lidar;
    case SensorType::kRgbd: return arm.rgbd;
    case SensorType::kLaser2d: return arm.laser;
    default: return arm.camera;
  }
}

// The arm's base on a table 0.75 m above the simulated room's floor.
Eigen::Isometry3d roomFromBase() {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(0.0, 0.0, 0.75);
  return pose;
}
}  // namespace

RigDescription simulatedHandEyeRig(HandEyeSetup setup, const TargetDescription& target, bool compressed_images, bool beside) {
  RigDescription rig;
  rig.reference_frame = kBase;
  rig.target = target;
  rig.target.parent = setup == HandEyeSetup::kEyeInHand ? kBase : kTool;
  RigSensorDescription camera;
  camera.spec = {"arm_camera", SensorType::kCamera, "arm_camera_optical"};
  camera.image_topic = compressed_images ? "/arm_camera/image_raw/compressed" : "/arm_camera/image_raw";
  camera.camera_info_topic = "/arm_camera/camera_info";
  if (setup == HandEyeSetup::kEyeInHand) camera.parent = kTool;
  rig.sensors.push_back(camera);
  if (beside && setup == HandEyeSetup::kEyeToHand) {
    RigSensorDescription lidar;
    lidar.spec = {"arm_lidar", SensorType::kLidar3d, "arm_lidar"};
    lidar.cloud_topic = "/arm_lidar/points";
    rig.sensors.push_back(lidar);
    RigSensorDescription rgbd;
    rgbd.spec = {"arm_rgbd", SensorType::kRgbd, "arm_rgbd_optical"};
    rgbd.depth_topic = "/arm_rgbd/depth/image";
    rgbd.camera_info_topic = "/arm_rgbd/depth/camera_info";
    rig.sensors.push_back(rgbd);
    RigSensorDescription laser;
    laser.spec = {"arm_laser", SensorType::kLaser2d, "arm_laser"};
    laser.scan_topic = "/arm_laser/scan";
    rig.sensors.push_back(laser);
  }
  if (beside && setup == HandEyeSetup::kEyeInHand) {
    RigSensorDescription laser;
    laser.spec = {"tool_laser", SensorType::kLaser2d, "tool_laser"};
    laser.scan_topic = "/tool_laser/scan";
    laser.parent = kTool;
    rig.sensors.push_back(laser);
  }
  rig.reference_sensor = -1;
  return rig;
}

void writeSimulatedHandEyeBag(const SimulatedArm& arm, const RigDescription& rig, const HandEyeBagOptions& options, const std::string& bag_path) {
  if (!(options.still_seconds > 0.0 && options.moving_seconds > 0.0 && options.camera_rate > 0.0 && options.tf_rate > 0.0)) {
    throw InputError(bag_path + ": the still and moving times and the camera and tf rates must be > 0");
  }
  rosbag::Bag bag;
  openBag(&bag, bag_path, rosbag::bagmode::Write);
  std::mt19937 rng(options.seed);
  const PinholeCamera camera = defaultKinectCamera(640, 480);
  const PinholeCamera depth_camera = defaultKinectCamera(320, 240);
  const CameraRays rays(camera, LensDistortion{});
  const double start = 1700000000.0;  // seconds, a plausible recording's stamps
  const double period = options.still_seconds + options.moving_seconds;
  const double end = period * static_cast<double>(arm.true_tool.size()) - options.moving_seconds;
  // The tool at time t: still at pose k, then interpolated to pose k + 1 (as reported; the truth alike).
  const auto toolAt = [&](double t, const std::vector<Eigen::Isometry3d>& poses) {
    const int k = std::min(static_cast<int>(t / period), static_cast<int>(poses.size()) - 1);
    const double into = t - k * period;
    if (into <= options.still_seconds || k + 1 >= static_cast<int>(poses.size())) return poses[k];
    const double alpha = (into - options.still_seconds) / options.moving_seconds;
    return interpolatePose(poses[k], poses[k + 1], 0.5 - 0.5 * std::cos(M_PI * alpha));  // smooth start and stop
  };
  tf2_msgs::TFMessage fixed;
  fixed.transforms.push_back(toTransformStamped(flangeFromTool(), kFlange, kTool, ros::Time(start)));
  bag.write("/tf_static", ros::Time(start), fixed);
  const int tf_messages = static_cast<int>(std::floor(end * options.tf_rate)) + 1;
  for (int i = 0; i < tf_messages; ++i) {
    const double t = i / options.tf_rate;
    const ros::Time stamp(start + t);
    tf2_msgs::TFMessage moving;
    moving.transforms.push_back(toTransformStamped(toolAt(t, arm.reported_tool) * flangeFromTool().inverse(), kBase, kFlange, stamp));
    bag.write("/tf", stamp, moving);
    if (options.joint_arm) {
      sensor_msgs::JointState state;
      state.header.stamp = stamp;
      for (const int j : options.joint_arm->allJoints()) state.name.push_back(options.joint_arm->joints[j].name);
      state.position = options.joint_arm->allReadingsAt(t, options.still_seconds, options.moving_seconds);
      bag.write("/joint_states", stamp, state);
    }
  }
  // Each sensor at the camera's rate, starting a little after the arm's first pose and a little after
  // one another, unsynchronised with tf.
  for (std::size_t s = 0; s < rig.sensors.size(); ++s) {
    const RigSensorDescription& d = rig.sensors[s];
    SimulatedSensor sensor{d.spec, Eigen::Isometry3d::Identity()};
    if ((d.parent == kForearm || d.parent == kHead) && !options.joint_arm)
      throw InputError(bag_path + ": a camera on the " + d.parent + " needs the robot's joints");
    double late = 0.0, focal_scale = 1.0;  // the sensor's faults of its stamps and its camera_info
    for (const SimulatedSensorFault& fault : options.faults) {
      if (fault.sensor != static_cast<int>(s)) continue;
      if (fault.kind == SimulatedSensorFault::Kind::kTimeOffset) late += fault.amount;
      if (fault.kind == SimulatedSensorFault::Kind::kFocalScale) focal_scale *= fault.amount;
    }
    PinholeCamera stated = camera;
    stated.fx *= focal_scale;
    stated.fy *= focal_scale;
    const int poses = static_cast<int>(arm.true_tool.size());
    for (double t = (0.5 + 0.3 * s) / options.camera_rate; t <= end; t += 1.0 / options.camera_rate) {
      const ros::Time stamp(start + t + late);
      const Eigen::Isometry3d tool = toolAt(t, arm.true_tool);
      const bool in_hand = arm.setup == HandEyeSetup::kEyeInHand;
      // In its parent, as the faults place it at this still pose (the one being left while moving).
      const int k = std::min(static_cast<int>(t / period), poses - 1);
      const auto placed = [&](const Eigen::Isometry3d& as_built) {
        return faultyPlacement(as_built, options.faults, static_cast<int>(s), k, poses, options.seed);
      };
      Eigen::Isometry3d base_from_sensor = d.parent == kTool ? tool * placed(sensorPoseInParent(arm, d)) : placed(sensorPoseInParent(arm, d));
      if (d.parent == kForearm) {
        base_from_sensor = options.joint_arm->forearmAt(options.joint_arm->anglesAt(t, options.still_seconds, options.moving_seconds)) *
                           placed(arm.forearm_camera);
      }
      if (d.parent == kHead) base_from_sensor = options.joint_arm->headAt(t, options.still_seconds, options.moving_seconds) * placed(arm.head_camera);
      sensor.reference_from_sensor = roomFromBase() * base_from_sensor;
      SimulatedRoomView view;
      view.sensor = &sensor;
      view.reference_from_target = roomFromBase() * (in_hand ? arm.board : tool * arm.board);
      view.target = &rig.target;
      view.range_noise = d.spec.type == SensorType::kLidar3d   ? options.lidar_noise
                         : d.spec.type == SensorType::kLaser2d ? options.laser_noise
                                                               : options.depth_noise;
      if (d.spec.type == SensorType::kLidar3d) {
        SimulatedTruth truth;
        const std::vector<Eigen::Vector3d> cloud = simulateLidarCloud(view, &rng, &truth);
        bag.write(d.cloud_topic, stamp, toLidarPointCloud2(cloud, truth.rings, d.spec.frame_id, stamp));
        continue;
      }
      if (d.spec.type == SensorType::kLaser2d) {  // a 270-degree scanner, 0.25-degree steps
        view.beam_aperture = options.laser_beam_aperture;
        view.beam_divergence = options.laser_beam_divergence;
        bag.write(d.scan_topic, stamp, toLaserScan(simulateLaserRanges(view, &rng), -135.0 * M_PI / 180.0, 0.25 * M_PI / 180.0, 8.0, d.spec.frame_id, stamp));
        continue;
      }
      if (d.spec.type == SensorType::kRgbd) {
        bag.write(d.camera_info_topic, stamp, toCameraInfo(depth_camera, d.spec.frame_id, stamp));
        bag.write(d.depth_topic, stamp, toDepth32FImage(simulateDepthImage(view, depth_camera, &rng), d.spec.frame_id, stamp));
        continue;
      }
      bag.write(d.camera_info_topic, stamp, toCameraInfo(stated, d.spec.frame_id, stamp));
      const ColorImage image = simulateCameraImage(view, rays, options.image_noise, &rng);
      if (options.compressed_images) {
        bag.write(d.image_topic, stamp, toCompressedJpeg(image, d.spec.frame_id, stamp));
      } else {
        bag.write(d.image_topic, stamp, toMono8Image(image, d.spec.frame_id, stamp));
      }
    }
  }
  bag.close();
}

RigDescription simulatedJointArmRig(HandEyeSetup setup, const TargetDescription& target, const SimulatedJointArm& joint_arm, bool beside,
                                    bool forearm) {
  const auto cameraOn = [](const std::string& name, const std::string& parent) {
    RigSensorDescription camera;
    camera.spec = {name, SensorType::kCamera, name + "_optical"};
    camera.image_topic = "/" + name + "/image_raw";
    camera.camera_info_topic = "/" + name + "/camera_info";
    camera.parent = parent;
    return camera;
  };
  RigDescription rig = simulatedHandEyeRig(setup, target, false, beside);
  if (forearm) rig.sensors.push_back(cameraOn("forearm_camera", kForearm));
  if (!joint_arm.head_chain.empty()) rig.sensors.push_back(cameraOn("head_camera", kHead));
  rig.joints = joint_arm.model_joints;
  return rig;
}

void writeHandEyeGroundTruth(const std::string& path, const SimulatedArm& arm, const RigDescription& rig, int poor_pose,
                             const SimulatedJointArm* joint_arm) {
  std::ofstream file(path);
  if (!file) throw InputError(path + ": cannot write the ground truth");
  const auto pose = [&](const Eigen::Isometry3d& p) {
    const Eigen::Quaterniond q(p.rotation());
    std::ostringstream out;
    out.precision(10);
    out << "{translation: [" << p.translation().x() << ", " << p.translation().y() << ", " << p.translation().z() << "], rotation: [" << q.x()
        << ", " << q.y() << ", " << q.z() << ", " << q.w() << "]}";
    return out.str();
  };
  const bool in_hand = arm.setup == HandEyeSetup::kEyeInHand;
  file << "# the simulated arm's truth: the camera and the board each in its parent frame\n"
       << "setup: " << handEyeSetupName(arm.setup) << "\n"
       << "camera: {parent: " << (in_hand ? kTool : kBase) << ", pose: " << pose(arm.camera) << "}\n"
       << "sensors:  # every sensor of the rig, by name\n";
  for (const RigSensorDescription& d : rig.sensors) {
    const Eigen::Isometry3d p = sensorPoseInParent(arm, d);
    file << "  " << d.spec.name << ": {parent: " << (d.parent.empty() ? rig.reference_frame : d.parent) << ", pose: " << pose(p) << "}\n";
  }
  file
       << "board: {parent: " << (in_hand ? rig.reference_frame : std::string(kTool)) << ", pose: " << pose(arm.board) << "}\n"
       << "poor_pose: " << (poor_pose >= 0 ? poor_pose + 1 : 0) << "  # numbered from 1, 0: none\n"
       << "tool_poses:  # base <- tool at each still pose: true, and as reported on /tf\n";
  for (std::size_t k = 0; k < arm.true_tool.size(); ++k) {
    file << "  - {true: " << pose(arm.true_tool[k]) << ", reported: " << pose(arm.reported_tool[k]) << "}\n";
  }
  if (joint_arm) {
    file << "joints:  # the arm's (then the head's), with their true zero offsets (added to each reading)\n";
    for (const int j : joint_arm->allJoints()) {
      const JointDescription& joint = joint_arm->joints[j];
      file << "  - {name: " << joint.name << ", offset: " << joint.offset;
      // An origin off the model's (a link length): the true one.
      if (!joint.origin.isApprox(joint_arm->model_joints[j].origin, 1e-12)) file << ", origin: " << pose(joint.origin);
      file << "}\n";
    }
    file << "arm_angles:  # the arm's true joint angles at each still pose\n";
    for (const std::vector<double>& a : joint_arm->angles) {
      file << "  - [";
      for (std::size_t j = 0; j < a.size(); ++j) file << (j ? ", " : "") << a[j];
      file << "]\n";
    }
    if (!joint_arm->head_angles.empty()) {
      file << "head_angles:  # the head's true joint angles at each still pose (pan, tilt)\n";
      for (const std::vector<double>& a : joint_arm->head_angles) file << "  - [" << a[0] << ", " << a[1] << "]\n";
    }
  }
  if (!file) throw InputError(path + ": write failed");
}

}  // namespace vocal
