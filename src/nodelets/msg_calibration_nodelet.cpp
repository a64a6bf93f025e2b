// Nodelet vocal/MsgCalibration: live MSG-Cal. Subscribes to every sensor topic of the rig description
// (parameter `rig`), extracts the target from each message as it arrives, and on the `calibrate`
// service associates the still poses, calibrates, writes the result files, publishes the extrinsics
// on /tf_static and the target points of every sensor in the reference frame (`fused_cloud`).
// A thin adapter over CalibrationSession, which calibrate_rig uses on bags.

#include <cstdio>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <sstream>
#include <string>

#include <diagnostic_updater/diagnostic_updater.h>
#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/JointState.h>
#include <sensor_msgs/LaserScan.h>
#include <sensor_msgs/PointCloud2.h>
#include <std_srvs/Empty.h>
#include <std_srvs/Trigger.h>
#include <tf2_eigen/tf2_eigen.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/static_transform_broadcaster.h>
#include <tf2_ros/transform_listener.h>

#include "vocal/calibration/calibration_session.h"
#include "vocal/calibration/output/calibration_output.h"
#include "vocal/calibration/urdf_joints.h"
#include "vocal/calibration/solver/pose_jackknife.h"
#include "vocal/core/errors.h"
#include "vocal/core/folders.h"
#include "vocal/core/se3.h"
#include "vocal/nodelets/message_conversions.h"

namespace vocal {

class MsgCalibrationNodelet : public nodelet::Nodelet {
 private:
  void onInit() override {
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    output_dir_ = pnh.param<std::string>("output_dir", "");
    if (!output_dir_.empty()) {
      try {
        makeFolders(output_dir_);  // now, not when the first result is written
      } catch (const InputError& e) {
        NODELET_ERROR_STREAM("MsgCalibration: parameter output_dir: " << e.what() << "; results will not be written");
        last_problem_ = "output_dir: " + std::string(e.what());
        output_dir_.clear();
      }
    }
    consensus_filter_ = pnh.param("consensus_filter", true);
    board_edges_ = pnh.param("board_edges", true);
    refine_intrinsics_ = pnh.param("refine_intrinsics", false);
    ring_offsets_.enabled = pnh.param("ring_offsets", true);
    publish_uncertain_ = pnh.param("publish_uncertain", false);
    isolate_ = pnh.param("isolate", true);
    const double max_held_mb = pnh.param("max_held_mb", memory_.max_held_mb);
    if (max_held_mb >= 0.0) memory_.max_held_mb = max_held_mb;
    else NODELET_WARN_STREAM("MsgCalibration: ~max_held_mb must be >= 0 (got " << max_held_mb << "): keeping " << memory_.max_held_mb);
    for (auto [name, value] : {std::pair<const char*, double*>{"tolerance_translation", &tolerance_.translation}, {"tolerance_rotation", &tolerance_.rotation}}) {
      const double given = pnh.param(name, *value);
      if (given > 0.0) *value = given;
      else NODELET_WARN_STREAM("MsgCalibration: ~" << name << " must be > 0 (got " << given << "): keeping " << *value);
    }
    const int queue_size = std::max(1, pnh.param("queue_size", 50));
    calibrate_service_ = pnh.advertiseService("calibrate", &MsgCalibrationNodelet::calibrate, this);
    reset_service_ = pnh.advertiseService("reset", &MsgCalibrationNodelet::reset, this);
    fused_cloud_pub_ = pnh.advertise<sensor_msgs::PointCloud2>("fused_cloud", 1, true);
    updater_ = std::make_unique<diagnostic_updater::Updater>(nh, pnh, getName());
    updater_->setHardwareID("vocal_msg_calibration");
    updater_->add("calibration", this, &MsgCalibrationNodelet::diagnose);
    diagnostics_timer_ = nh.createWallTimer(ros::WallDuration(1.0), [this](const ros::WallTimerEvent&) { updater_->update(); });

    std::string rig_path;
    if (!pnh.getParam("rig", rig_path)) {
      setup_error_ = "parameter '" + pnh.resolveName("rig") + "' (the rig description YAML) is not set";
      NODELET_ERROR_STREAM("MsgCalibration: " << setup_error_ << "; the nodelet stays idle");
      return;
    }
    try {
      RigDescription described = readRigDescription(rig_path);
      if (!described.imus.empty()) {
        // A waved session's every frame and IMU sample: calibrate_rig on its recording, not live yet.
        throw InputError(rig_path + ": imu '" + described.imus.front().name + "' is calibrated from a recorded session (rosbag record its "
                         "camera and IMU topics while waving the rig before the board, then calibrate_rig RIG.yaml BAG), not live yet");
      }
      if (!described.urdf_param.empty()) {
        // The robot's joints from its URDF on the parameter server (what robot_state_publisher reads).
        std::string urdf;
        if (!nh.getParam(described.urdf_param, urdf)) {
          throw InputError(rig_path + ": urdf_param '" + nh.resolveName(described.urdf_param) + "' is not on the parameter server (load the "
                           "robot's URDF there, or give the file as 'urdf:')");
        }
        setRigJoints(&described, urdfJointsFromString(urdf, nh.resolveName(described.urdf_param)), rig_path);
      }
      session_ = std::make_unique<CalibrationSession>(std::move(described), TargetExtractionOptions{}, StillnessOptions{},
                                                      ring_offsets_, memory_);
    } catch (const InputError& e) {
      setup_error_ = e.what();
      NODELET_ERROR_STREAM("MsgCalibration: " << setup_error_ << "; the nodelet stays idle");
      return;
    }
    const RigDescription& rig = session_->rig();
    dropped_.assign(rig.sensors.size(), 0);
    arm_ = rig.handEye();
    reference_frame_ = rig.reference_frame;
    if (arm_ && !arm_->from_joints) {
      // The arm's tool from live tf, sampled faster than any arm's still pose is short.
      tf_buffer_ = std::make_unique<tf2_ros::Buffer>();
      tf_listener_ = std::make_unique<tf2_ros::TransformListener>(*tf_buffer_, nh);
      tool_timer_ = nh.createWallTimer(ros::WallDuration(0.01), [this](const ros::WallTimerEvent&) { sampleTool(); });
    }
    needs_joint_states_ = rig.needsJointStates();
    if (needs_joint_states_) {
      // Sensors (or an arm's tool) behind joints: the joints' positions at the rate the robot publishes them (100-1000 Hz).
      subscribers_.push_back(nh.subscribe<sensor_msgs::JointState>(
          rig.joint_states_topic, 1000, [this](const sensor_msgs::JointState::ConstPtr& m) { onJointState(*m); }));
    }
    for (std::size_t s = 0; s < rig.sensors.size(); ++s) {
      const RigSensorDescription& d = rig.sensors[s];
      const int sensor = static_cast<int>(s);
      switch (d.spec.type) {
        case SensorType::kCamera:
        case SensorType::kRgbd: {
          subscribers_.push_back(nh.subscribe<sensor_msgs::CameraInfo>(
              d.camera_info_topic, 5, [this, sensor](const sensor_msgs::CameraInfo::ConstPtr& m) { onCameraInfo(sensor, *m); }));
          const bool depth = d.spec.type == SensorType::kRgbd;
          if (!depth && isCompressedImageTopic(d.image_topic)) {
            subscribers_.push_back(nh.subscribe<sensor_msgs::CompressedImage>(
                d.image_topic, queue_size, [this, sensor](const sensor_msgs::CompressedImage::ConstPtr& m) { onCompressedImage(sensor, *m); }));
            break;
          }
          subscribers_.push_back(nh.subscribe<sensor_msgs::Image>(
              depth ? d.depth_topic : d.image_topic, queue_size,
              [this, sensor, depth](const sensor_msgs::Image::ConstPtr& m) { onImage(sensor, depth, *m); }));
          break;
        }
        case SensorType::kLidar3d:
          subscribers_.push_back(nh.subscribe<sensor_msgs::PointCloud2>(
              d.cloud_topic, queue_size, [this, sensor](const sensor_msgs::PointCloud2::ConstPtr& m) { onCloud(sensor, *m); }));
          break;
        case SensorType::kLaser2d:
          subscribers_.push_back(nh.subscribe<sensor_msgs::LaserScan>(
              d.scan_topic, queue_size, [this, sensor](const sensor_msgs::LaserScan::ConstPtr& m) { onScan(sensor, *m); }));
          break;
      }
    }
    NODELET_INFO_STREAM("MsgCalibration: " << rig.sensors.size() << " sensors from " << rig_path << "; move the target, hold it "
                                           << "still at many poses, then call " << calibrate_service_.getService());
  }

  // The tool's newest pose in tf, once per stamp; a lookup that fails is counted (diagnostics).
  void sampleTool() {
    geometry_msgs::TransformStamped t;
    try {
      t = tf_buffer_->lookupTransform(reference_frame_, arm_->tool_frame, ros::Time(0));
    } catch (const tf2::TransformException& e) {
      std::lock_guard<std::mutex> lock(mutex_);
      ++tool_lookups_failed_;
      tool_problem_ = e.what();
      return;
    }
    std::lock_guard<std::mutex> lock(mutex_);
    if (t.header.stamp <= last_tool_stamp_) return;
    last_tool_stamp_ = t.header.stamp;
    session_->addToolPose(t.header.stamp.toSec(), tf2::transformToEigen(t));
    ++tool_poses_;
  }

  // ~calibrate for a hand-eye rig: the arm's still poses, each sensor in the tool frame (on the tool) or
  // the reference frame (fixed), /tf_static from there to each sensor not withheld.
  void calibrateHandEyeRig(std_srvs::Trigger::Response& response) {
    const RigDescription& rig = session_->rig();
    const HandEyeAssociation association = session_->handEyeAssociation();
    const HandEyeFrames frames = handEyeFrames(rig, *arm_);
    HandEyeOptions options = session_->handEyeOptions();  // an arm whose tool comes from its joints, the board's size
    options.intrinsics.enabled = refine_intrinsics_;
    const HandEyeResult result = calibrateArmRig(frames.solverSensors(), !arm_->eye_in_hand, association.stations, options);
    std::ostringstream summary;
    summary << "calibrated " << rig.sensors.size() << " sensor" << (rig.sensors.size() == 1 ? "" : "s") << " (" << handEyeSetupName(result.setup)
            << ") from " << association.stations.size() << " still arm poses";
    for (std::size_t i = 0; i < result.joints.size() && options.arm_joints; ++i) {
      if (!result.joints[i].reported) continue;
      const JointDescription& joint = options.arm_joints->joints[options.arm_joints->readJoints()[i]];
      summary << "; joint " << joint.name << " offset " << jointOffsetText(joint, result.joints[i]);
      if (result.joints[i].origin_free) summary << ", " << jointOriginText(result.joints[i]);
    }
    std::vector<std::string> withheld;
    std::vector<geometry_msgs::TransformStamped> transforms;
    const ros::Time now = ros::Time::now();
    for (std::size_t s = 0; s < rig.sensors.size(); ++s) {
      const Eigen::Vector3d t = result.sensors[s].translation();
      const Eigen::Quaterniond q(result.sensors[s].rotation());
      char line[400];
      std::snprintf(line, sizeof(line),
                    "; %s in %s at [%.5f %.5f %.5f] [%.6f %.6f %.6f %.6f] (x y z, qx qy qz qw), sigma %.2f mm / %.2f mrad, spread across "
                    "the arm's poses %.2f mm / %.2f mrad",
                    rig.sensors[s].spec.frame_id.c_str(), frames.parentOf(s).c_str(), t.x(), t.y(), t.z(), q.x(), q.y(), q.z(), q.w(),
                    1000 * result.sensor_sigmas[s].head<3>().norm(), 1000 * result.sensor_sigmas[s].tail<3>().norm(),
                    1000 * result.sensor_spreads[s].head<3>().norm(), 1000 * result.sensor_spreads[s].tail<3>().norm());
      summary << line;
      withheld.push_back(handEyeWithheld(result, s, rig.sensors[s].spec.type, tolerance_, publish_uncertain_));
      if (withheld.back().empty()) {
        transforms.push_back(toTransformStamped(result.sensors[s], frames.parentOf(s), rig.sensors[s].spec.frame_id, now));
      } else {
        summary << "; withheld from /tf_static: " << rig.sensors[s].spec.name << " (" << withheld.back()
                << "); set ~publish_uncertain to publish anyway";
      }
    }
    for (const int k : result.poor_stations) summary << "; poor arm pose " << k + 1 << " (it does not pull the result)";
    for (const HandEyeClosedForm& c : result.closed_forms) {
      char line[160];
      std::snprintf(line, sizeof(line), "%s %.2f mm / %.3f deg", c.method.c_str(), 1000 * (c.camera.translation() - result.camera().translation()).norm(),
                    rotationAngle(result.camera().inverse() * c.camera) * 180 / M_PI);
      summary << (&c == &result.closed_forms.front() ? "; OpenCV's closed forms for " + rig.sensors[result.main_camera].spec.name + " against it: "
                                                     : std::string(", "))
              << line;
    }
    if (!output_dir_.empty()) {
      writeHandEyeYaml(output_dir_ + "/calibration.yaml", frames, result, withheld);
      writeHandEyeUrdf(output_dir_ + "/calibration.urdf", frames, result, withheld);
      writeHandEyeLaunch(output_dir_ + "/calibration.launch", frames, result, withheld);
      summary << "; wrote " << output_dir_ << "/calibration.yaml, .urdf, .launch";
    }
    if (!transforms.empty()) static_broadcaster_.sendTransform(transforms);
    last_result_ = summary.str();
    response.success = transforms.size() == rig.sensors.size();
    response.message = summary.str();
    NODELET_INFO_STREAM("MsgCalibration: " << summary.str());
  }

  // Runs one message through the session; a bad one is counted against its sensor, never thrown.
  template <typename F>
  void guarded(int sensor, const F& add) {
    std::lock_guard<std::mutex> lock(mutex_);
    try {
      add();
    } catch (const std::exception& e) {
      ++dropped_[sensor];
      last_problem_ = e.what();
      NODELET_WARN_STREAM_THROTTLE(5.0, "MsgCalibration: message dropped: " << e.what());
    }
  }

  void onCameraInfo(int sensor, const sensor_msgs::CameraInfo& msg) {
    guarded(sensor, [&] {
      const std::string& topic = session_->rig().sensors[sensor].camera_info_topic;
      const PinholeCamera camera = fromCameraInfo(msg, topic);
      lenses_[sensor] = lensDistortionFromCameraInfo(msg, topic);
      cameras_[sensor] = camera;
    });
  }

  void onImage(int sensor, bool depth, const sensor_msgs::Image& msg) {
    guarded(sensor, [&] {
      const RigSensorDescription& d = session_->rig().sensors[sensor];
      const std::string& topic = depth ? d.depth_topic : d.image_topic;
      const auto camera = cameras_.find(sensor);
      if (camera == cameras_.end()) throw InputError(topic + ": no usable camera_info on " + d.camera_info_topic + " yet");
      if (depth) {
        session_->addDepth(sensor, msg.header.stamp.toSec(), fromDepthImage(msg, topic), camera->second);
      } else {
        session_->addImage(sensor, msg.header.stamp.toSec(), fromColorImage(msg, topic), camera->second, lenses_[sensor]);
      }
    });
  }

  void onCompressedImage(int sensor, const sensor_msgs::CompressedImage& msg) {
    guarded(sensor, [&] {
      const RigSensorDescription& d = session_->rig().sensors[sensor];
      const auto camera = cameras_.find(sensor);
      if (camera == cameras_.end()) throw InputError(d.image_topic + ": no usable camera_info on " + d.camera_info_topic + " yet");
      session_->addImage(sensor, msg.header.stamp.toSec(), fromCompressedColorImage(msg, d.image_topic), camera->second, lenses_[sensor]);
    });
  }

  void onJointState(const sensor_msgs::JointState& msg) {
    std::lock_guard<std::mutex> lock(mutex_);
    try {
      session_->addJointState(msg.header.stamp.toSec(), msg.name, msg.position);
      ++joint_states_;
    } catch (const std::exception& e) {
      ++joint_states_dropped_;
      last_problem_ = session_->rig().joint_states_topic + ": " + e.what();
      NODELET_WARN_STREAM_THROTTLE(5.0, "MsgCalibration: joint state dropped: " << last_problem_);
    }
  }

  void onCloud(int sensor, const sensor_msgs::PointCloud2& msg) {
    guarded(sensor, [&] {
      std::vector<int> rings;
      const std::vector<Eigen::Vector3d> points = fromPointCloud2(msg, session_->rig().sensors[sensor].cloud_topic, &rings);
      session_->addCloud(sensor, msg.header.stamp.toSec(), points, rings);
    });
  }

  void onScan(int sensor, const sensor_msgs::LaserScan& msg) {
    guarded(sensor, [&] {
      session_->addScan(sensor, msg.header.stamp.toSec(), fromLaserScan(msg, session_->rig().sensors[sensor].scan_topic));
    });
  }

  bool calibrate(std_srvs::Trigger::Request&, std_srvs::Trigger::Response& response) {
    std::unique_lock<std::mutex> lock(mutex_);
    if (!setup_error_.empty()) {
      response.success = false;
      response.message = setup_error_;
      return true;
    }
    if (arm_) {
      try {
        calibrateHandEyeRig(response);
      } catch (const InputError& e) {
        response.success = false;
        response.message = e.what();
        last_problem_ = e.what();
        NODELET_WARN_STREAM("MsgCalibration: calibration failed: " << e.what());
      }
      return true;
    }
    try {
      CalibrationOptions options;
      options.consensus_filter = consensus_filter_;
      options.board_edges.enabled = board_edges_;
      options.intrinsics.enabled = refine_intrinsics_;
      options.trust.isolate = isolate_;
      const RigDescription rig = session_->rig();  // a copy: ~reset may replace the session meanwhile
      const std::vector<SensorSpec> specs = rig.specs();
      const CalibrationOptions solved_with = session_->calibrationOptions(options);
      // Before association: the lidars' board points depend on whether their offsets are applied. Judging
      // them re-solves twice per still pose (seconds): messages are taken meanwhile.
      const std::vector<CalibrationSession::RingOffsetTrial> trials = session_->ringOffsetTrials();
      const CalibrationSession* const judged = session_.get();
      lock.unlock();
      std::vector<RingOffsetChoice> choices;
      for (const CalibrationSession::RingOffsetTrial& trial : trials) choices.push_back(judgeRingOffsets(specs, trial, solved_with));
      lock.lock();
      if (session_.get() != judged) throw InputError("the session was reset (~reset) while it was being calibrated: call ~calibrate again");
      for (std::size_t t = 0; t < trials.size(); ++t) session_->recordRingOffsetChoice(trials[t].sensor, choices[t]);
      const std::vector<std::optional<RingOffsets>> ring_offsets = session_->ringOffsets();
      const std::vector<TargetObservation> associated = session_->associatedObservations();
      const CalibrationResult result = session_->calibrate(associated, options);
      // The spread across still poses re-solves once per pose (seconds): messages are taken meanwhile.
      lock.unlock();
      std::optional<PoseJackknife> spread;
      try {
        spread = jackknifeOverPoses(specs, associated, solved_with, result);
      } catch (const InputError& e) {
        NODELET_INFO_STREAM("MsgCalibration: no spread across poses: " << e.what());
      }
      lock.lock();
      std::ostringstream summary;
      summary << (result.trusted ? "calibrated " : "NOT TRUSTED (" + result.failure + ") ") << rig.sensors.size()
              << " sensors, rms " << result.rms * 1000 << " mm";
      if (spread) {
        summary << "; spread across poses (jackknife), solver's sigma in brackets:";
        const char* separator = " ";
        for (std::size_t s = 0; s < specs.size(); ++s) {
          if (static_cast<int>(s) == rig.reference_sensor) continue;
          char line[160];
          std::snprintf(line, sizeof(line), "%s%s %.2f mm (%.2f) / %.2f mrad (%.2f)", separator, specs[s].name.c_str(),
                        1000 * spread->standard_deviation[s].head<3>().norm(), 1000 * result.sensors[s].standard_deviation.head<3>().norm(),
                        1000 * spread->standard_deviation[s].tail<3>().norm(), 1000 * result.sensors[s].standard_deviation.tail<3>().norm());
          summary << line;
          separator = ", ";
        }
        for (const std::string& uncertain : spreadOverTolerance(*spread, specs, tolerance_)) summary << "; uncertain: " << uncertain;
      }
      for (std::size_t s = 0; s < specs.size(); ++s) {
        if (!ring_offsets[s]) continue;
        const RingOffsets& rings = *ring_offsets[s];
        char line[160] = "";
        if (rings.offsets.size() > 0) {
          std::snprintf(line, sizeof(line), "%+.1f to %+.1f mm (from %d room planes) ", 1000 * rings.offsets.minCoeff(),
                        1000 * rings.offsets.maxCoeff(), rings.planes);
        }
        summary << "; " << specs[s].name << " ring offsets " << line << rings.verdict;
        if (!rings.warning.empty()) summary << "; warning: " << specs[s].name << ": " << rings.warning;
      }
      for (const ClockOffset& clock : session_->clockOffsets())
        if (clock.applied || !clock.refused.empty()) summary << "; clock: " << describeClockOffset(clock, specs);
      for (const ObservabilityWarning& w : result.warnings) summary << "; warning: " << w.message;
      // Sensors behind joints: each joint's offset, or why it was held, and which joint needs more motion.
      for (std::size_t j = 0; j < result.joints.size(); ++j) {
        if (!result.joints[j].reported) continue;
        summary << "; joint " << result.mounts.joints[j].name << " offset " << jointOffsetText(result.mounts.joints[j], result.joints[j]);
        if (result.joints[j].origin_free) summary << ", " << jointOriginText(result.joints[j]);
      }
      if (session_->memory().full) summary << "; " << fullSessionAdvice(true);
      bool any_distrusted = false;
      for (std::size_t s = 0; s < specs.size(); ++s) {
        if (result.sensors[s].distrust.empty()) continue;
        summary << "; NOT TRUSTED: " << specs[s].name << ": " << result.sensors[s].distrust;
        any_distrusted = true;
      }
      const std::vector<std::string> withheld =
          withheldSensors(specs, rig.reference_sensor, result, spread ? &*spread : nullptr, tolerance_, publish_uncertain_);
      bool any_withheld = false;
      for (std::size_t s = 0; s < specs.size(); ++s) {
        if (withheld[s].empty()) continue;
        // A sensor not trusted was named with its cause above.
        summary << "; withheld from /tf_static: " << specs[s].name << " ("
                << (result.sensors[s].distrust.empty() ? withheld[s] : std::string("not trusted")) << ")";
        any_withheld = true;
      }
      if (any_withheld && result.trusted) {
        summary << "; calibrate again as the NOT TRUSTED or uncertain lines say, or set ~publish_uncertain to publish anyway";
      }
      if (!output_dir_.empty()) {
        writeCalibrationYaml(output_dir_ + "/calibration.yaml", rig.reference_frame, specs, result, spread ? &*spread : nullptr,
                             &ring_offsets, &withheld);
        writeUrdfSnippet(output_dir_ + "/calibration.urdf", rig.reference_frame, specs, result, &withheld);
        writeStaticTransformLaunch(output_dir_ + "/calibration.launch", rig.reference_frame, specs, result, &withheld);
        summary << "; wrote " << output_dir_ << "/calibration.yaml, .urdf, .launch";
      }
      const ros::Time now = ros::Time::now();
      std::vector<geometry_msgs::TransformStamped> transforms;
      for (std::size_t s = 0; s < specs.size(); ++s) {
        if (!withheld[s].empty()) continue;
        transforms.push_back(
            toTransformStamped(result.sensors[s].reference_from_sensor, sensorParent(result, s, rig.reference_frame), specs[s].frame_id, now));
      }
      if (!transforms.empty()) static_broadcaster_.sendTransform(transforms);
      // Every sensor's target points in the reference frame, one colour per sensor: they must coincide.
      std::vector<ColoredPoint> fused;
      const Rgb8 palette[] = {{230, 25, 75}, {60, 180, 75}, {0, 130, 200}, {245, 130, 48}, {145, 30, 180}, {70, 240, 240}};
      for (const TargetObservation& o : associated) {
        for (const Eigen::Vector3d& p : o.points) {
          fused.push_back({(result.rigFromSensorAt(o) * p).cast<float>(), palette[o.sensor % 6]});
        }
      }
      fused_cloud_pub_.publish(toPointCloud2(fused, rig.reference_frame, now));
      last_result_ = summary.str();
      response.success = result.trusted && !any_distrusted;  // a script acting on success applies no sensor it cannot trust
      response.message = summary.str();
      NODELET_INFO_STREAM("MsgCalibration: " << summary.str());
    } catch (const InputError& e) {
      response.success = false;
      response.message = e.what();
      if (session_->memory().full) response.message += "; " + fullSessionAdvice(true);
      last_problem_ = e.what();
      NODELET_WARN_STREAM("MsgCalibration: calibration failed: " << e.what());
    }
    return true;
  }

  bool reset(std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
    std::lock_guard<std::mutex> lock(mutex_);
    if (session_) {
      session_ = std::make_unique<CalibrationSession>(session_->rig(), TargetExtractionOptions{}, StillnessOptions{}, ring_offsets_, memory_);
    }
    dropped_.assign(dropped_.size(), 0);
    tool_poses_ = tool_lookups_failed_ = 0;
    joint_states_ = joint_states_dropped_ = 0;
    tool_problem_.clear();
    last_problem_.clear();
    last_result_.clear();
    return true;
  }

  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& status) {
    std::lock_guard<std::mutex> lock(mutex_);
    using diagnostic_msgs::DiagnosticStatus;
    if (!setup_error_.empty()) {
      status.summary(DiagnosticStatus::ERROR, setup_error_);
      return;
    }
    if (session_->memory().full) {  // before a dropped message's problem: it holds for the rest of the session
      status.summary(DiagnosticStatus::WARN, fullSessionAdvice());
    } else if (!last_problem_.empty()) {
      status.summary(DiagnosticStatus::WARN, last_problem_);
    } else {
      status.summary(DiagnosticStatus::OK, last_result_.empty() ? "collecting observations" : last_result_);
    }
    const RigDescription& rig = session_->rig();
    const std::vector<SensorDataCounts> counts = session_->counts();
    for (std::size_t s = 0; s < rig.sensors.size(); ++s) {
      const SensorDataCounts& c = counts[s];
      std::ostringstream value;
      value << c.target_found << " of " << c.received << " messages show the target, " << dropped_[s] << " dropped";
      if (c.only_background > 0) value << ", " << c.only_background << " only static board-shaped segments";
      if (c.not_kept > 0) value << ", " << c.not_kept << " not kept (the session is full)";
      if (c.views_with_corners_left_out > 0) value << ", " << c.views_with_corners_left_out << " with a misdetected corner left out";
      status.add(rig.sensors[s].spec.name, value.str());
    }
    status.add("memory", session_->memorySummary());
    if (arm_ && !arm_->from_joints) {
      std::ostringstream tool;
      tool << tool_poses_ << " poses of " << arm_->tool_frame << " in " << rig.reference_frame << " from tf, " << tool_lookups_failed_
           << " lookups failed" << (tool_problem_.empty() ? "" : " (last: " + tool_problem_ + ")");
      status.add("tool", tool.str());
    }
    if (needs_joint_states_) {
      std::ostringstream joints;
      joints << joint_states_ << " joint states on " << rig.joint_states_topic << " (" << session_->jointReadings()
             << " readings of the rig's joints kept), " << joint_states_dropped_ << " dropped";
      status.add("joints", joints.str());
    }
  }

  // What to do about a full session: while collecting (diagnostics), and in a ~calibrate reply.
  std::string fullSessionAdvice(bool in_reply = false) const {
    std::ostringstream advice;
    if (in_reply) {
      advice << "the session was full (~max_held_mb " << memory_.max_held_mb
             << "): still poses after it filled were not kept; for more, raise ~max_held_mb and ~reset";
    } else {
      advice << "the session is full (~max_held_mb " << memory_.max_held_mb
             << "): later still poses are not kept; call ~calibrate now, or raise ~max_held_mb and ~reset";
    }
    return advice.str();
  }

  std::string output_dir_, setup_error_, last_problem_, last_result_;
  bool consensus_filter_ = true;
  bool board_edges_ = true;  // the board's outline as well as its plane (a pose per still pose)
  bool refine_intrinsics_ = false;  // the cameras' focal lengths refined with the poses
  RingOffsetOptions ring_offsets_;  // a 3D lidar's range offset per ring from the room's planes (~ring_offsets)
  SessionMemoryOptions memory_;     // ~max_held_mb: the session's budget for target data
  bool publish_uncertain_ = false;  // ~publish_uncertain: uncertain and untrusted sensors go to /tf_static too
  bool isolate_ = true;             // ~isolate: a sensor that disagrees with the rest is solved out of the graph
  SpreadTolerance tolerance_;  // beyond it a sensor's spread across poses is reported as uncertain
  std::mutex mutex_;
  std::unique_ptr<CalibrationSession> session_;
  std::map<int, PinholeCamera> cameras_;
  std::map<int, LensDistortion> lenses_;  // camera_info's D, for cameras
  std::vector<std::size_t> dropped_;
  std::vector<ros::Subscriber> subscribers_;
  ros::ServiceServer calibrate_service_, reset_service_;
  ros::Publisher fused_cloud_pub_;
  tf2_ros::StaticTransformBroadcaster static_broadcaster_;
  std::unique_ptr<diagnostic_updater::Updater> updater_;
  ros::WallTimer diagnostics_timer_;
  // A hand-eye rig (RigDescription::handEye): the arm's tool from tf.
  std::optional<HandEyeRig> arm_;
  std::string reference_frame_;  // the rig's, read without the session (~reset replaces it)
  std::unique_ptr<tf2_ros::Buffer> tf_buffer_;
  std::unique_ptr<tf2_ros::TransformListener> tf_listener_;
  ros::WallTimer tool_timer_;
  ros::Time last_tool_stamp_;
  std::size_t tool_poses_ = 0, tool_lookups_failed_ = 0;
  std::size_t joint_states_ = 0, joint_states_dropped_ = 0;  // on the rig's joint_states_topic
  bool needs_joint_states_ = false;  // RigDescription::needsJointStates, once
  std::string tool_problem_;
};

}  // namespace vocal

PLUGINLIB_EXPORT_CLASS(vocal::MsgCalibrationNodelet, nodelet::Nodelet)
