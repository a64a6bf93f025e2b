// Nodelet vocal/IcpDvoOdometry: registered RGB + depth + camera_info in, odometry out (nav_msgs/Odometry
// with covariances, tf odom -> base, the current cloud, a voxel-fused cloud, the path, diagnostics).
// A thin adapter: parameters -> OdometryConfig, messages -> RgbdFrame, IcpDvoOdometry does the work.
// Topic and parameter names follow rtabmap_ros's rgbd_odometry.

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <deque>
#include <iomanip>
#include <memory>
#include <mutex>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <diagnostic_updater/diagnostic_updater.h>
#include <image_transport/image_transport.h>
#include <image_transport/subscriber_filter.h>
#include <message_filters/subscriber.h>
#include <message_filters/sync_policies/approximate_time.h>
#include <message_filters/sync_policies/exact_time.h>
#include <message_filters/synchronizer.h>
#include <nav_msgs/Odometry.h>
#include <nav_msgs/Path.h>
#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>
#include <ros/ros.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/PointCloud2.h>
#include <std_srvs/Empty.h>
#include <tf2_eigen/tf2_eigen.h>
#include <tf2_ros/buffer.h>
#include <tf2_ros/transform_broadcaster.h>
#include <tf2_ros/transform_listener.h>
#include <yaml-cpp/yaml.h>

#include "vocal/core/colored_point.h"
#include "vocal/core/errors.h"
#include "vocal/core/frame_rate_report.h"
#include "vocal/core/gravity.h"
#include "vocal/core/lap_timer.h"
#include "vocal/core/se3.h"
#include "vocal/core/stream_silence.h"
#include "vocal/core/voxel_cloud_map.h"
#include "vocal/nodelets/message_conversions.h"
#include "vocal/nodelets/parameter_yaml.h"
#include "vocal/odometry/icp_dvo_odometry.h"
#include "vocal/odometry/odometry_config_yaml.h"
#include "vocal/odometry/resolution_governor.h"

namespace vocal {

namespace {
using ImageMsg = sensor_msgs::Image;
using CameraInfoMsg = sensor_msgs::CameraInfo;
using ApproximatePolicy = message_filters::sync_policies::ApproximateTime<ImageMsg, ImageMsg, CameraInfoMsg>;
using ExactPolicy = message_filters::sync_policies::ExactTime<ImageMsg, ImageMsg, CameraInfoMsg>;

// nav_msgs covariance (row-major 6x6, x y z then rotation about x y z) from a [v; w] covariance.
void copyCovariance(const Matrix6d& covariance, boost::array<double, 36>* out) {
  for (int r = 0; r < 6; ++r)
    for (int c = 0; c < 6; ++c) (*out)[6 * r + c] = covariance(r, c);
}

geometry_msgs::Pose toPoseMsg(const Eigen::Isometry3d& pose) { return tf2::toMsg(pose); }

// How bad a state is, for the worst since the last diagnostics report.
int severity(TrackingState state) {
  switch (state) {
    case TrackingState::kLost: return 3;
    case TrackingState::kPredicted: return 2;
    case TrackingState::kDegraded: return 1;
    default: return 0;
  }
}

// One synchronised frame waiting for the worker.
struct PendingFrame {
  ImageMsg::ConstPtr rgb, depth;
  CameraInfoMsg::ConstPtr info;
  std::size_t received = 0;  // frames received by its arrival, itself included (the stream's count)
  // When it arrived (steady clock, seconds): the pace to keep is the arrivals', which a bag played at
  // another rate than 1 makes differ from the stamps'.
  double arrived = 0.0;
};

// Sums of the per-stage wall-clock times, reported as means per processed frame.
struct StageTimes {
  double conversion = 0.0, preprocess = 0.0, features = 0.0, solve = 0.0, clouds = 0.0;
};
}  // namespace

class IcpDvoOdometryNodelet : public nodelet::Nodelet {
 public:
  ~IcpDvoOdometryNodelet() override {
    {
      std::lock_guard<std::mutex> lock(pending_mutex_);
      stopping_ = true;
    }
    pending_ready_.notify_all();
    if (worker_.joinable()) worker_.join();
  }

 private:
  void onInit() override {
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    frame_id_ = pnh.param<std::string>("frame_id", "");
    odom_frame_id_ = pnh.param<std::string>("odom_frame_id", "odom");
    publish_tf_ = pnh.param("publish_tf", true);
    wait_for_transform_ = pnh.param("wait_for_transform", 0.2);
    cloud_stride_ = std::max(1, pnh.param("cloud_stride", 4));
    fused_cloud_every_ = std::max(1, pnh.param("fused_cloud_every", 10));
    const double fused_cloud_period = pnh.param("fused_cloud_period", 1.0);
    stream_timeout_ = pnh.param("stream_timeout", 5.0);
    const bool approx_sync = pnh.param("approx_sync", true);
    skip_to_newest_ = pnh.param("skip_to_newest", true);
    const int queue_size = std::max(1, pnh.param("queue_size", 10));
    imu_topic_ = pnh.param<std::string>("imu_topic", "");
    imu_noise_.gyro_noise_density = pnh.param("gyro_noise_density", imu_noise_.gyro_noise_density);
    imu_noise_.gyro_bias_random_walk = pnh.param("gyro_bias_random_walk", imu_noise_.gyro_bias_random_walk);
    imu_noise_.accel_noise_density = pnh.param("accel_noise_density", imu_noise_.accel_noise_density);
    imu_noise_.accel_bias_random_walk = pnh.param("accel_bias_random_walk", imu_noise_.accel_bias_random_walk);
    imu_time_offset_ = pnh.param("imu_time_offset", 0.0);
    imu_wait_ = std::max(0.0, pnh.param("imu_wait", 0.03));
    try {
      XmlRpc::XmlRpcValue parameters;
      YAML::Node settings;
      if (pnh.getParam("", parameters)) settings = toYaml(parameters);
      config_ = odometryConfigFromYaml(settings, "parameters of " + pnh.getNamespace(), OdometryConfig{}, true);
      fused_map_ = std::make_unique<VoxelCloudMap>(pnh.param("fused_cloud_voxel", 0.02),
                                                   static_cast<std::size_t>(pnh.param("fused_cloud_max_voxels", 100000)));
    } catch (const InputError& e) {
      setupError(e.what());
      return;
    }
    // Only a stream that skips frames has a pace to keep; every frame in order is tracked at full size.
    keepPaceAt(config_.keep_pace_row_step);

    odom_pub_ = nh.advertise<nav_msgs::Odometry>("odom", 10);
    path_pub_ = nh.advertise<nav_msgs::Path>("path", 1);
    cloud_pub_ = nh.advertise<sensor_msgs::PointCloud2>("cloud", 2);
    fused_cloud_pub_ = nh.advertise<sensor_msgs::PointCloud2>("fused_cloud", 1, true);
    reset_service_ = nh.advertiseService("reset_odom", &IcpDvoOdometryNodelet::resetOdometry, this);
    tf_buffer_ = std::make_unique<tf2_ros::Buffer>();
    tf_listener_ = std::make_unique<tf2_ros::TransformListener>(*tf_buffer_, nh);

    updater_ = std::make_unique<diagnostic_updater::Updater>(nh, pnh, getName());
    updater_->setHardwareID("vocal_icp_dvo_odometry");
    updater_->add("odometry", this, &IcpDvoOdometryNodelet::diagnose);
    diagnostics_timer_ = nh.createWallTimer(ros::WallDuration(1.0), [this](const ros::WallTimerEvent&) { updater_->update(); });
    watchdog_timer_ = nh.createWallTimer(ros::WallDuration(5.0), &IcpDvoOdometryNodelet::watchdog, this);
    // Publishing costs the whole map's size, so a timer does it at most once a period (only the copy of
    // the map's points holds the tracking lock): a 10,000-frame soak fell from 30 to 19 Hz while every
    // new keyframe published the growing map.
    fused_cloud_timer_ = nh.createWallTimer(ros::WallDuration(std::max(0.05, fused_cloud_period)),
                                            [this](const ros::WallTimerEvent&) { publishFusedCloud(); });

    if (!imu_topic_.empty()) {
      // The accelerometer levels odom at the first frame: its mean there, gravity, turns odom z up.
      // On the multi-threaded queue: the first frame waits for these (with skip_to_newest false it is
      // tracked on this nodelet's own single-threaded queue).
      imu_sub_ = getMTNodeHandle().subscribe<sensor_msgs::Imu>(imu_topic_, 200,
                                                               [this](const sensor_msgs::Imu::ConstPtr& m) { onImu(*m); });
    }

    image_transport::ImageTransport rgb_it(nh), depth_it(nh);
    const image_transport::TransportHints rgb_hints("raw", ros::TransportHints(), pnh, "rgb_image_transport");
    const image_transport::TransportHints depth_hints("raw", ros::TransportHints(), pnh, "depth_image_transport");
    rgb_sub_.subscribe(rgb_it, "rgb/image", queue_size, rgb_hints);
    depth_sub_.subscribe(depth_it, "depth/image", queue_size, depth_hints);
    info_sub_.subscribe(nh, "rgb/camera_info", queue_size);
    // Arrivals per topic, so a missing stream can be named.
    rgb_sub_.registerCallback([this](const ImageMsg::ConstPtr&) { ++rgb_count_, rgb_silence_.arrived(); });
    depth_sub_.registerCallback([this](const ImageMsg::ConstPtr&) { ++depth_count_, depth_silence_.arrived(); });
    info_sub_.registerCallback([this](const CameraInfoMsg::ConstPtr&) { ++info_count_, info_silence_.arrived(); });
    // Frames are tracked on a worker thread, newest first: a frame that arrives while one is being
    // tracked replaces any frame still waiting (counted as skipped), so no queue and no latency grow
    // when the camera is faster than the estimator.
    worker_ = std::thread([this] { trackNewestFrames(); });
    if (approx_sync) {
      approximate_ = std::make_unique<message_filters::Synchronizer<ApproximatePolicy>>(ApproximatePolicy(queue_size), rgb_sub_,
                                                                                          depth_sub_, info_sub_);
      approximate_->registerCallback(&IcpDvoOdometryNodelet::onFrame, this);
    } else {
      exact_ = std::make_unique<message_filters::Synchronizer<ExactPolicy>>(ExactPolicy(queue_size), rgb_sub_, depth_sub_,
                                                                              info_sub_);
      exact_->registerCallback(&IcpDvoOdometryNodelet::onFrame, this);
    }
    NODELET_INFO_STREAM("IcpDvoOdometry: " << odometryModeName(config_.mode) << " odometry on " << rgb_sub_.getTopic() << ", "
                                           << depth_sub_.getTopic() << ", " << info_sub_.getTopic() << " ("
                                           << (approx_sync ? "approximate" : "exact") << " sync), publishing "
                                           << odom_frame_id_ << " -> " << (frame_id_.empty() ? "<camera frame>" : frame_id_));
  }

  void setupError(const std::string& message) {
    setup_error_ = message;
    NODELET_ERROR_STREAM("IcpDvoOdometry: " << message << "; the nodelet stays idle");
  }

  void onImu(const sensor_msgs::Imu& msg) {
    ++imu_count_;
    std::lock_guard<std::mutex> lock(imu_mutex_);
    try {
      const AccelerometerSample sample = fromImuAcceleration(msg, imu_topic_);
      imu_frame_ = msg.header.frame_id;
      accelerometer_.push_back(sample);
      // Only the samples around the first frame are read: two seconds are kept.
      while (!accelerometer_.empty() && accelerometer_.front().stamp < sample.stamp - 2.0) accelerometer_.pop_front();
      // A gyro (REP-145: angular_velocity_covariance[0] -1 says there is none, as a Kinect's driver sends):
      // its rates for the rotation prior, the last few seconds.
      if (msg.angular_velocity_covariance[0] != -1.0) {
        const ImuSample rates = fromImuMessage(msg, imu_topic_);
        if (!gyro_samples_.empty() && !(rates.stamp > gyro_samples_.back().stamp)) {
          std::ostringstream message;
          message << imu_topic_ << ": stamp " << msg.header.stamp << " is not after the previous message's (out of order): dropped";
          throw InputError(message.str());
        }
        gyro_samples_.push_back(rates);
        while (!gyro_samples_.empty() && gyro_samples_.front().stamp < rates.stamp - 5.0) gyro_samples_.pop_front();
      }
    } catch (const InputError& e) {
      ++imu_dropped_;
      NODELET_WARN_STREAM_THROTTLE(5.0, "IcpDvoOdometry: " << e.what());
    }
  }

  // With mutex_ held. The gyro's rotation from the last frame to this one: waits up to imu_wait for
  // the samples past it; none (and `gyro_problem_` says why) without a gyro, its tf or its samples.
  std::optional<RotationPrior> gyroPrior(const std::string& camera_frame, const ros::Time& stamp) {
    if (imu_topic_.empty() || last_stamp_.isZero()) return std::nullopt;
    const double needed = stamp.toSec() + imu_time_offset_;
    std::vector<ImuSample> fresh;
    std::string imu_frame;
    const ros::WallTime give_up = ros::WallTime::now() + ros::WallDuration(imu_wait_);
    while (true) {
      {
        std::lock_guard<std::mutex> lock(imu_mutex_);
        // An accelerometer alone (no rates ever came) is not waited for.
        const bool covered = !gyro_samples_.empty() && gyro_samples_.back().stamp >= needed;
        if (covered || gyro_samples_.empty() || ros::WallTime::now() >= give_up || !ros::ok()) {
          const double after = gyro_ && !gyro_->samples().empty() ? gyro_->samples().back().stamp : -1.0;
          for (const ImuSample& sample : gyro_samples_)
            if (sample.stamp > after) fresh.push_back(sample);
          imu_frame = imu_frame_;
          break;
        }
      }
      ros::WallDuration(0.002).sleep();
    }
    if (!gyro_) {
      if (fresh.empty()) {
        gyro_problem_ = imu_topic_ + ": no angular velocity yet (an accelerometer alone levels odom only)";
        return std::nullopt;
      }
      ImuExtrinsics extrinsics;
      extrinsics.imu_frame = imu_frame, extrinsics.camera_frame = camera_frame;
      extrinsics.time_offset = imu_time_offset_;
      extrinsics.noise = imu_noise_;
      try {
        extrinsics.camera_in_imu = tf2::transformToEigen(tf_buffer_->lookupTransform(imu_frame, camera_frame, ros::Time(0)));
      } catch (const tf2::TransformException& e) {
        gyro_problem_ = "tf " + imu_frame + " <- " + camera_frame + " unavailable (the gyro's pose in the camera): " + e.what();
        return std::nullopt;
      }
      gyro_ = std::make_unique<GyroRotationPrior>(extrinsics);
      NODELET_INFO_STREAM("IcpDvoOdometry: gyro on " << imu_topic_ << " (" << imu_frame << ") as a rotation prior, time offset "
                                                     << imu_time_offset_ << " s, bias estimated online");
    }
    gyro_->add(fresh);
    gyro_->forgetBefore(last_stamp_.toSec());
    std::string why;
    std::optional<RotationPrior> prior = gyro_->between(last_stamp_.toSec(), stamp.toSec(), &why);
    if (!prior) gyro_problem_ = imu_topic_ + ": " + why + " (waited " + std::to_string(imu_wait_) + " s)";
    return prior;
  }

  // The accelerometer's last seconds in the camera frame, on the camera's clock: what holds roll and pitch
  // to gravity (config gravity_time_constant). Empty without one, with the correction off, or without tf
  // from its frame to the camera's (said in the diagnostics).
  std::vector<AccelerometerSample> accelerometerInCamera(const std::string& camera_frame) {
    std::vector<AccelerometerSample> samples;
    if (imu_topic_.empty() || !(config_.gravity_time_constant > 0.0)) return samples;
    std::string imu_frame;
    {
      std::lock_guard<std::mutex> lock(imu_mutex_);
      samples.assign(accelerometer_.begin(), accelerometer_.end());
      imu_frame = imu_frame_;
    }
    if (samples.empty()) return samples;
    if (camera_from_accelerometer_frame_ != imu_frame) {
      try {
        camera_from_accelerometer_ =
            tf2::transformToEigen(tf_buffer_->lookupTransform(camera_frame, imu_frame, ros::Time(0))).linear();
        camera_from_accelerometer_frame_ = imu_frame;
      } catch (const tf2::TransformException& e) {
        gravity_problem_ = "tf " + camera_frame + " <- " + imu_frame + " unavailable (the accelerometer's pose in the camera): " + e.what();
        return {};
      }
    }
    for (AccelerometerSample& sample : samples) {
      sample.stamp -= imu_time_offset_;
      sample.specific_force = camera_from_accelerometer_ * sample.specific_force;
    }
    return samples;
  }

  // odom <- the base at the first frame: level (z up, the heading kept) where the accelerometer's mean
  // around that frame is gravity, else the identity (odom is then the base's first pose), with why.
  Eigen::Isometry3d levelledStart(const std::string& base_frame, const ros::Time& stamp, std::string* how) {
    if (imu_topic_.empty()) {
      *how = "not levelled: no imu_topic (odom is the first pose of " + base_frame + ")";
      return Eigen::Isometry3d::Identity();
    }
    std::vector<AccelerometerSample> samples;
    std::string imu_frame;
    // The samples after the frame come on their own topic, maybe later than the frame: waited for up
    // to kImuWaitSeconds, once per start.
    const ros::WallTime give_up = ros::WallTime::now() + ros::WallDuration(kImuWaitSeconds);
    for (;;) {
      {
        std::lock_guard<std::mutex> lock(imu_mutex_);
        if ((!accelerometer_.empty() && accelerometer_.back().stamp >= stamp.toSec() + kGravityWindowSeconds) ||
            ros::WallTime::now() >= give_up) {
          samples.assign(accelerometer_.begin(), accelerometer_.end());
          imu_frame = imu_frame_;
          break;
        }
      }
      ros::WallDuration(0.01).sleep();
    }
    std::string why;
    const std::optional<Eigen::Vector3d> force = stillSpecificForce(samples, stamp.toSec(), kGravityWindowSeconds, &why);
    Eigen::Isometry3d base_from_imu = Eigen::Isometry3d::Identity();
    if (force && imu_frame != base_frame) {
      try {
        base_from_imu = tf2::transformToEigen(tf_buffer_->lookupTransform(base_frame, imu_frame, stamp, ros::Duration(wait_for_transform_)));
      } catch (const tf2::TransformException& e) {
        why = "tf " + base_frame + " <- " + imu_frame + " unavailable: " + e.what();
      }
    }
    if (!force || !why.empty()) {
      *how = "not levelled: " + imu_topic_ + ": " + why + " (odom is the first pose of " + base_frame + ")";
      return Eigen::Isometry3d::Identity();
    }
    const Eigen::Vector3d up = base_from_imu.linear() * *force;
    Eigen::Isometry3d level = Eigen::Isometry3d::Identity();
    level.linear() = levelFromUp(up);
    std::ostringstream text;
    text << "levelled by the accelerometer on " << imu_topic_ << " (" << base_frame << " started "
         << std::fixed << std::setprecision(1) << std::acos(std::clamp(up.normalized().z(), -1.0, 1.0)) * 180.0 / M_PI
         << " deg from level)";
    *how = text.str();
    return level;
  }

  void onFrame(const ImageMsg::ConstPtr& rgb, const ImageMsg::ConstPtr& depth, const CameraInfoMsg::ConstPtr& info) {
    const std::size_t received = ++frames_received_;
    const double arrived = std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
    if (!skip_to_newest_) {
      trackFrame({rgb, depth, info, received, arrived});  // every frame, in the synchroniser's thread
      return;
    }
    {
      std::lock_guard<std::mutex> lock(pending_mutex_);
      if (pending_.rgb) ++frames_skipped_;
      pending_ = {rgb, depth, info, received, arrived};
    }
    pending_ready_.notify_one();
  }

  void trackNewestFrames() {
    while (true) {
      PendingFrame frame;
      {
        std::unique_lock<std::mutex> lock(pending_mutex_);
        pending_ready_.wait(lock, [this] { return stopping_ || pending_.rgb; });
        if (stopping_) return;
        std::swap(frame, pending_);
      }
      trackFrame(frame);
    }
  }

  void trackFrame(const PendingFrame& frame) {
    std::lock_guard<std::mutex> lock(mutex_);
    const auto started = std::chrono::steady_clock::now();
    const int resolution = governor_ ? governor_->resolution() : 0;
    bool paced = false;
    try {
      paced = track(*frame.rgb, *frame.depth, *frame.info, resolutions_[resolution]);
    } catch (const std::exception& e) {
      // Bad input is counted and reported; it never reaches the manager.
      ++frames_dropped_;
      last_problem_ = e.what();
      NODELET_WARN_STREAM_THROTTLE(5.0, "IcpDvoOdometry: frame dropped: " << e.what());
    }
    ++frames_processed_;
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    processing_seconds_ += seconds;
    if (governor_ && !paced) governor_->sawFrame(frame.arrived, frame.received);
    if (governor_ && paced) {
      governor_->tracked(resolution, seconds, frame.arrived, frame.received);
      // Coarser and finer apart, so that a failed try at full resolution is not hidden by its start.
      const int next = governor_->resolution();
      if (next > resolution) NODELET_INFO_STREAM_THROTTLE(10.0, "IcpDvoOdometry: " << paceText(next, resolution));
      if (next < resolution) NODELET_INFO_STREAM_THROTTLE(10.0, "IcpDvoOdometry: " << paceText(next, resolution));
    }
  }

  // The resolutions a stream that skips frames keeps pace at (with a row step of `row_step` before the
  // coarser levels) and the governor choosing among them; none for a stream of every frame in order. It
  // starts at the row step (as accurate as every row, lighter through the first, slowest frames), else
  // at the coarsest level.
  void keepPaceAt(int row_step) {
    resolutions_ = keepPaceResolutions(config_.levels, config_.keep_pace_max_level, row_step);
    governor_.reset();
    if (skip_to_newest_ && resolutions_.size() > 1) {
      const int coarsest = static_cast<int>(resolutions_.size()) - 1;
      governor_.emplace(coarsest, row_step > 1 ? 1 : coarsest);
    }
  }

  // "WxH" of the camera at resolution `resolution`'s pyramid level ("0x0" before the first frame), and
  // its row step where it has one: "640x480 every 2nd row".
  std::string resolutionText(int resolution) const {
    const TrackingResolution& r = resolutions_.at(resolution);
    const int width = odometry_ ? odometry_->camera().width : 0, height = odometry_ ? odometry_->camera().height : 0;
    std::string text = std::to_string(width >> r.level) + "x" + std::to_string(height >> r.level);
    if (r.row_step > 1) text += " every " + std::to_string(r.row_step) + (r.row_step == 2 ? "nd" : r.row_step == 3 ? "rd" : "th") + " row";
    return text;
  }

  // Why the next frames are tracked at resolution `level` after `previous` (the governor's choices), for
  // the log and the diagnostics.
  std::string paceText(int level, int previous) const {
    std::ostringstream text;
    text << std::fixed << std::setprecision(1) << "tracking at " << resolutionText(level) << " (level " << resolutions_.at(level).level
         << ")";
    if (level > previous && !(governor_->secondsAt(previous) > 0.0)) {
      text << " as the stream starts (its first frames are the slowest; " << resolutionText(previous) << " is tried after "
           << ResolutionGovernor::kStartProbeWaitFrames << " frames)";
      return text.str();
    }
    text << (level > previous ? " to keep pace with the " : ": there is time again in the ")
         << (governor_->period() > 0.0 ? 1.0 / governor_->period() : 0.0) << " Hz stream (" << resolutionText(previous) << " took "
         << 1000.0 * governor_->secondsAt(previous) << " ms a frame against a budget of " << 1000.0 * governor_->budget()
         << " ms; keep_pace_max_level " << config_.keep_pace_max_level << ", keep_pace_row_step " << config_.keep_pace_row_step << ")";
    return text.str();
  }

  // `resolution`: the finest pyramid level to track at and its row step (the governor's choice). Returns
  // whether the frame was tracked against another, what the governor times (a first frame only builds
  // the estimator and the reference).
  bool track(const ImageMsg& rgb, const ImageMsg& depth, const CameraInfoMsg& info, TrackingResolution resolution) {
    if (!setup_error_.empty()) throw InputError(setup_error_);
    auto clock = std::chrono::steady_clock::now();
    if (!last_stamp_.isZero() && rgb.header.stamp <= last_stamp_) {
      const double back = (last_stamp_ - rgb.header.stamp).toSec();
      if (back <= kRestartAfterJumpBackSeconds) {
        ++frames_out_of_order_;
        std::ostringstream message;
        message << rgb_sub_.getTopic() << ": stamp " << rgb.header.stamp << " is not after the previous frame's "
                << last_stamp_ << " (out of order; a jump back of more than " << kRestartAfterJumpBackSeconds
                << " s restarts the odometry)";
        throw InputError(message.str());
      }
      // A looped or restarted bag, or a restarted camera: the old track means nothing for this stream.
      ++time_jumps_back_;
      NODELET_WARN_STREAM("IcpDvoOdometry: " << rgb_sub_.getTopic() << ": stamps jumped back " << back
                                             << " s (a looped or restarted bag, or a restarted camera): the odometry restarts at the origin");
      reset();
    }
    const PinholeCamera camera = fromCameraInfo(info, info_sub_.getTopic());
    if (camera.width != static_cast<int>(rgb.width) || camera.height != static_cast<int>(rgb.height)) {
      std::ostringstream message;
      message << info_sub_.getTopic() << ": camera_info is " << camera.width << "x" << camera.height << " but "
              << rgb_sub_.getTopic() << " is " << rgb.width << "x" << rgb.height;
      throw InputError(message.str());
    }
    std::string lens_problem;
    const LensDistortion lens = odometryLensFromCameraInfo(info, info_sub_.getTopic(), &lens_problem);
    if (!lens_problem.empty()) NODELET_WARN_STREAM_ONCE("IcpDvoOdometry: " << lens_problem);
    const RgbdFrame frame = toRgbdFrame(rgb, depth, rgb_sub_.getTopic(), depth_sub_.getTopic());
    stage_sums_.conversion += lapMilliseconds(&clock);
    if (!odometry_ || !(odometry_->camera() == camera) || !(odometry_->lens() == lens)) {
      // First frame, or new intrinsics: the estimator is built for one camera. The camera is already
      // validated, so a failure here is the configuration's (e.g. backend opencl without a platform).
      try {
        odometry_ = std::make_unique<IcpDvoOdometry>(camera, config_, nullptr, lens);
      } catch (const InputError& e) {
        setupError(e.what());
        throw;
      }
      backend_name_ = odometry_->backend().name();
      NODELET_INFO_STREAM("IcpDvoOdometry: " << camera.width << "x" << camera.height << " camera, backend " << backend_name_
                                             << "; " << odometry_->cameraModelText());
      if (governor_ && config_.keep_pace_row_step > 1 && !odometry_->backend().samplesRows()) {
        NODELET_INFO_STREAM("IcpDvoOdometry: backend " << backend_name_ << " tracks every row: keep_pace_row_step "
                                                   << config_.keep_pace_row_step << " left out");
        keepPaceAt(1);
      }
    }
    const std::string camera_frame = rgb.header.frame_id;
    const std::string base_frame = frame_id_.empty() ? camera_frame : frame_id_;
    Eigen::Isometry3d base_from_camera = Eigen::Isometry3d::Identity();
    if (base_frame != camera_frame) {
      try {
        base_from_camera = tf2::transformToEigen(
            tf_buffer_->lookupTransform(base_frame, camera_frame, rgb.header.stamp, ros::Duration(wait_for_transform_)));
      } catch (const tf2::TransformException& e) {
        throw InputError("tf " + base_frame + " <- " + camera_frame + " unavailable: " + e.what());
      }
    }

    const std::optional<RotationPrior> gyro = gyroPrior(camera_frame, rgb.header.stamp);
    if (!imu_topic_.empty() && !last_stamp_.isZero()) ++(gyro ? gyro_priors_ : gyro_missing_);
    const std::vector<AccelerometerSample> accelerometer = accelerometerInCamera(camera_frame);
    odometry_->setFinestLevel(resolution.level, resolution.row_step);
    const OdometryResult result = odometry_->track(frame, gyro ? &*gyro : nullptr, accelerometer.empty() ? nullptr : &accelerometer);
    const bool paced = !result.first_frame;
    if (result.gravity_error_deg >= 0.0) gravity_error_deg_ = result.gravity_error_deg;
    if (gyro_) {
      if (result.state == TrackingState::kTracking && result.quality.trusted) {
        gyro_->observe(result.keyframe_stamp, rgb.header.stamp.toSec(), result.vision_rotation);
      } else {
        gyro_->breakWindow();
      }
    }
    if (result.first_frame) {
      odom_from_start_ = levelledStart(base_frame, rgb.header.stamp, &odom_levelling_);
      NODELET_INFO_STREAM("IcpDvoOdometry: odom " << odom_levelling_);
    }
    stage_sums_.preprocess += result.timings.preprocess_ms;
    stage_sums_.features += result.timings.features_ms;
    stage_sums_.solve += result.timings.solve_ms;
    // An increment spans the previous frame, trusted or not, to this one: velocities divide by that.
    const double dt = last_stamp_.isZero() ? 0.0 : (rgb.header.stamp - last_stamp_).toSec();
    last_stamp_ = rgb.header.stamp;
    state_ = result.state;
    lost_frames_ = result.lost_frames;
    if (severity(result.state) > severity(worst_since_report_)) worst_since_report_ = result.state;
    keyframe_id_ = result.keyframe_id;
    keyframes_ += result.new_keyframe;
    window_links_ += result.window_links;
    window_links_skipped_ += result.window_links_skipped;
    if (!result.window_error.empty()) NODELET_ERROR_STREAM("IcpDvoOdometry: " << result.window_error);
    const bool trusted = result.quality.trusted;
    if (!trusted) {
      ++frames_lost_;
      frames_predicted_ += result.state == TrackingState::kPredicted;
      last_problem_ = result.failure;
      NODELET_WARN_STREAM_THROTTLE(5.0, "IcpDvoOdometry: " << trackingEvent(result));
    } else {
      ++frames_tracked_;
      last_problem_.clear();
      quality_ = result.quality;
      if (result.state == TrackingState::kDegraded) {
        ++frames_degraded_;
        last_degraded_ = result.degraded;
        NODELET_WARN_STREAM_THROTTLE(5.0, "IcpDvoOdometry: degraded: " << result.degraded);
      }
      if (result.state == TrackingState::kRelocalised) {
        ++relocalisations_;
        NODELET_INFO_STREAM("IcpDvoOdometry: " << trackingEvent(result));
      }
    }

    // Every frame gets its odometry: tracked, predicted (the last motion repeated, its covariance
    // grown) or lost (the pose stays, the covariance says nothing is known and tf is not moved on).
    // The odometry frame is the base's pose at the first frame, levelled where the accelerometer allowed
    // (L): odom <- base = L B (cam0 <- cam) B^-1.
    const Eigen::Isometry3d& B = base_from_camera;
    const Eigen::Isometry3d odom_from_base = odom_from_start_ * B * result.pose * B.inverse();
    const Matrix6d to_base = adjoint(B);
    const Matrix6d to_odom = adjoint(odom_from_start_ * B);
    nav_msgs::Odometry odom;
    odom.header.stamp = rgb.header.stamp;
    odom.header.frame_id = odom_frame_id_;
    odom.child_frame_id = base_frame;
    odom.pose.pose = toPoseMsg(odom_from_base);
    copyCovariance(to_odom * result.pose_covariance * to_odom.transpose(), &odom.pose.covariance);
    if (!result.first_frame && dt > 0.0) {
      const Vector6d twist = se3Log(B * result.increment * B.inverse()) / dt;
      odom.twist.twist.linear.x = twist[0], odom.twist.twist.linear.y = twist[1], odom.twist.twist.linear.z = twist[2];
      odom.twist.twist.angular.x = twist[3], odom.twist.twist.angular.y = twist[4], odom.twist.twist.angular.z = twist[5];
      // Measured only while tracking: a predicted motion was assumed, and a relocalised frame's increment
      // also holds the correction of the prediction before it.
      const bool measured = result.state == TrackingState::kTracking || result.state == TrackingState::kDegraded;
      const Matrix6d twist_covariance = measured ? Matrix6d(to_base * result.covariance * to_base.transpose() / (dt * dt))
                                            : Matrix6d(Matrix6d::Identity() * 1e6);
      copyCovariance(twist_covariance, &odom.twist.covariance);
    }
    odom_pub_.publish(odom);
    if (result.state == TrackingState::kLost) return paced;
    if (publish_tf_) tf_broadcaster_.sendTransform(toTransformStamped(odom_from_base, odom_frame_id_, base_frame, rgb.header.stamp));

    geometry_msgs::PoseStamped stamped;
    stamped.header = odom.header;
    stamped.pose = odom.pose.pose;
    path_.header = odom.header;
    // Bounded for a robot that runs for days: past kMaxPathPoses every other pose goes and from then on
    // only every path_stride_-th is added, so the path still spans the whole run.
    if (frames_on_path_++ % path_stride_ == 0) path_.poses.push_back(stamped);
    if (path_.poses.size() >= kMaxPathPoses) {
      std::size_t kept = 0;
      for (std::size_t i = 0; i < path_.poses.size(); i += 2) path_.poses[kept++] = path_.poses[i];
      path_.poses.resize(kept);
      path_stride_ *= 2;
    }
    if (path_pub_.getNumSubscribers() > 0) path_pub_.publish(path_);
    if (!trusted) return paced;

    // The map keeps growing while nobody watches, so a late rviz sees the whole run. It takes each new
    // keyframe (frame to frame: every fused_cloud_every-th tracked frame; consecutive frames overlap
    // almost entirely, and adding each one cost the odometry about 2 ms a frame) and is published
    // right after.
    clock = std::chrono::steady_clock::now();
    const bool map_frame = config_.tracking_reference == TrackingReference::kKeyframe
                               ? result.new_keyframe
                               : (frames_tracked_ - 1) % fused_cloud_every_ == 0;
    const bool cloud_wanted = cloud_pub_.getNumSubscribers() > 0;
    if (map_frame || cloud_wanted) {
      // As tracked: undistorted, rows at one instant.
      const std::vector<ColoredPoint> points =
          backProjectFrame(odometry_->rectifying() ? odometry_->lastRectifiedFrame() : frame, camera, cloud_stride_);
      if (cloud_wanted) cloud_pub_.publish(toPointCloud2(points, camera_frame, rgb.header.stamp));
      if (map_frame) {
        fused_map_->add(points, odom_from_base * base_from_camera);
        fused_map_stamp_ = rgb.header.stamp;  // published by publishFusedCloud
      }
    }
    stage_sums_.clouds += lapMilliseconds(&clock);
    return paced;
  }

  void publishFusedCloud() {
    if (fused_cloud_pub_.getNumSubscribers() == 0) return;
    std::vector<ColoredPoint> points;
    ros::Time stamp;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (!fused_map_ || fused_map_stamp_.isZero() || fused_map_stamp_ == published_fused_map_stamp_) return;
      points = fused_map_->points();
      stamp = published_fused_map_stamp_ = fused_map_stamp_;
    }
    fused_cloud_pub_.publish(toPointCloud2(points, odom_frame_id_, stamp));
  }

  bool resetOdometry(std_srvs::Empty::Request&, std_srvs::Empty::Response&) {
    std::lock_guard<std::mutex> lock(mutex_);
    reset();
    NODELET_INFO("IcpDvoOdometry: odometry reset; the next frame starts at the origin");
    return true;
  }

  // With mutex_ held.
  void reset() {
    if (odometry_) odometry_->reset();
    if (governor_) governor_->reset();
    last_stamp_ = ros::Time();
    state_ = worst_since_report_ = TrackingState::kTracking;
    lost_frames_ = 0;
    path_.poses.clear();
    frames_on_path_ = 0;
    path_stride_ = 1;
    if (fused_map_) fused_map_->clear();
    fused_map_stamp_ = published_fused_map_stamp_ = ros::Time();
    ++resets_;
  }

  void watchdog(const ros::WallTimerEvent&) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      const bool progressed = frames_received_ != frames_received_at_watchdog_;
      frames_received_at_watchdog_ = frames_received_;
      if (progressed || !setup_error_.empty()) return;
    }
    NODELET_WARN_STREAM("IcpDvoOdometry: no synchronised frame in 5 s; received so far " << rgb_sub_.getTopic() << ": "
                                                                                        << rgb_count_ << ", " << depth_sub_.getTopic()
                                                                                        << ": " << depth_count_ << ", "
                                                                                        << info_sub_.getTopic() << ": " << info_count_);
  }

  // "TOPIC: nothing for N s" for each input topic that once arrived and has been silent for stream_timeout.
  std::string silentTopics() const {
    const std::pair<std::string, const StreamSilence*> topics[] = {
        {rgb_sub_.getTopic(), &rgb_silence_}, {depth_sub_.getTopic(), &depth_silence_}, {info_sub_.getTopic(), &info_silence_}};
    std::ostringstream message;
    for (const auto& [topic, silence] : topics) {
      const double silent = silence->seconds();
      if (!silence->heard() || silent < stream_timeout_) continue;
      message << (message.tellp() > 0 ? "; " : "") << topic << ": nothing for " << std::fixed << std::setprecision(1) << silent << " s";
    }
    if (message.tellp() > 0) message << " (stopped? frames resume when every stream is back)";
    return message.str();
  }

  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& status) {
    std::lock_guard<std::mutex> lock(mutex_);
    using diagnostic_msgs::DiagnosticStatus;
    const std::size_t received = frames_received_;
    const FrameRatePeriod period =
        rate_report_.update(std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(), received,
                            frames_processed_, frames_skipped_.load(), processing_seconds_);
    // Frames skipped for want of time: said in the summary and the log, never as a growing lag.
    const std::string skip_warning = frameSkipWarning(period);
    if (!skip_warning.empty()) NODELET_WARN_STREAM_THROTTLE(10.0, "IcpDvoOdometry: " << skip_warning);
    if (!setup_error_.empty()) {
      status.summary(DiagnosticStatus::ERROR, setup_error_);
    } else if (received == 0) {
      status.summary(DiagnosticStatus::WARN, "no synchronised rgb/depth/camera_info frame received yet");
    } else if (const std::string silent = silentTopics(); !silent.empty()) {
      // A stream that stopped (a driver that died, a bag that ended): no frame can be tracked until it is back.
      status.summary(DiagnosticStatus::WARN, silent);
    } else if (worst_since_report_ == TrackingState::kLost && state_ != TrackingState::kLost) {
      status.summary(DiagnosticStatus::ERROR, std::string("lost since the last report, now ") + trackingStateName(state_));
    } else if (state_ == TrackingState::kLost || state_ == TrackingState::kPredicted) {
      std::ostringstream message;
      message << (state_ == TrackingState::kLost ? "lost" : "predicting from the last motion") << " for " << lost_frames_
              << " frames: " << last_problem_;
      status.summary(state_ == TrackingState::kLost ? DiagnosticStatus::ERROR : DiagnosticStatus::WARN, message.str());
    } else if (state_ == TrackingState::kDegraded) {
      // Vision holds only some directions (a blank wall, one plane, darkness): the gyro and the motion
      // model the rest, which the odometry's covariance marks.
      status.summary(DiagnosticStatus::WARN, "degraded: " + last_degraded_);
    } else if (!skip_warning.empty()) {
      status.summary(DiagnosticStatus::WARN, skip_warning);
    } else if (!last_problem_.empty()) {
      status.summary(DiagnosticStatus::WARN, last_problem_);
    } else {
      std::string summary = trackingStateName(state_);
      if (governor_ && governor_->resolution() > 0 && odometry_) summary += " at " + resolutionText(governor_->resolution()) + " to keep pace with the stream";
      status.summary(DiagnosticStatus::OK, summary);
    }
    status.add("backend", backend_name_.empty() ? "not started" : backend_name_);
    status.add("odom", odom_levelling_.empty() ? "no frame yet" : odom_levelling_);
    if (!imu_topic_.empty()) {
      status.add(imu_topic_ + " messages", imu_count_.load());
      status.add(imu_topic_ + " messages dropped", imu_dropped_.load());
      status.add("frames with the gyro's rotation prior", gyro_priors_);
      status.add("frames without it", gyro_missing_);
      if (gyro_missing_ > 0) status.add("why not (last)", gyro_problem_);
      if (config_.gravity_time_constant > 0.0) {
        std::ostringstream gravity;
        if (gravity_error_deg_ >= 0.0) {
          gravity << std::fixed << std::setprecision(2) << gravity_error_deg_ << " deg (last), pulled back with a "
                  << config_.gravity_time_constant << " s time constant";
        } else {
          gravity << "not measured yet" << (gravity_problem_.empty() ? "" : ": " + gravity_problem_);
        }
        status.add("roll / pitch off the first level by (accelerometer)", gravity.str());
      }
      if (gyro_) {
        const Eigen::Vector3d bias = gyro_->bias() * 180.0 / M_PI;
        std::ostringstream text;
        text << std::fixed << std::setprecision(3) << bias.x() << " " << bias.y() << " " << bias.z() << " (+- "
             << gyro_->biasSigma().maxCoeff() * 180.0 / M_PI << ")";
        status.add("gyro bias (deg/s)", text.str());
      }
    }
    status.add("frames received", received);
    status.add("frames skipped", frames_skipped_.load());
    status.add("frames received per second (last report period)", period.received_hz);
    status.add("frames processed per second (last report period)", period.processed_hz);
    if (governor_) {
      // Frames tracked below the input's resolution to keep pace (keep_pace_row_step, keep_pace_max_level).
      std::ostringstream counts;
      for (std::size_t resolution = 0; resolution < governor_->framesAt().size(); ++resolution) {
        counts << (resolution ? ", " : "") << resolutionText(static_cast<int>(resolution)) << ": " << governor_->framesAt()[resolution];
      }
      status.add("frames tracked at each resolution (keep_pace_row_step, keep_pace_max_level)", counts.str());
      const int now = governor_->resolution();
      status.add("tracking at", now == 0 ? std::string("the input's resolution") : paceText(now, now - 1));
      if (config_.keep_pace_refines_keyframes && config_.local_window_keyframes == 0) {
        // Keyframes made coarser than the input, their link solved again at its resolution (and those skipped:
        // the last one's was still being solved).
        status.add("keyframes linked again at the input's resolution (keep_pace_refines_keyframes)", window_links_);
        status.add("keyframes not linked again (the last still solving)", window_links_skipped_);
      }
    }
    status.add("frames tracked", frames_tracked_);
    status.add("frames lost", frames_lost_);
    status.add("frames predicted", frames_predicted_);
    status.add("frames degraded (vision held only some directions)", frames_degraded_);
    status.add("tracking state", trackingStateName(state_));
    // A loss shorter than the report period would otherwise go unseen by whoever watches diagnostics.
    status.add("worst state since last report", trackingStateName(worst_since_report_));
    worst_since_report_ = state_;
    status.add("relocalisations", relocalisations_);
    status.add("keyframes", keyframes_);
    status.add("keyframe", keyframe_id_);
    if (config_.local_window_keyframes > 0) {
      status.add("local window links", window_links_);
      // New keyframes whose links were not solved: the last ones were still being solved (background).
      status.add("local window keyframes skipped", window_links_skipped_);
    }
    status.add("frames dropped", frames_dropped_);
    status.add("frames out of order", frames_out_of_order_);
    status.add("resets", resets_);
    status.add("restarts after stamps jumped back", time_jumps_back_);
    status.add("path poses", path_.poses.size());
    status.add(rgb_sub_.getTopic() + " messages", rgb_count_.load());
    status.add(depth_sub_.getTopic() + " messages", depth_count_.load());
    status.add(info_sub_.getTopic() + " messages", info_count_.load());
    const double per_frame = frames_processed_ ? 1.0 / frames_processed_ : 0.0;
    status.add("mean processing ms", 1000.0 * processing_seconds_ * per_frame);
    status.add("mean conversion ms", stage_sums_.conversion * per_frame);
    status.add("mean preprocessing ms", stage_sums_.preprocess * per_frame);
    status.add("mean features ms", stage_sums_.features * per_frame);
    status.add("mean solve ms", stage_sums_.solve * per_frame);
    status.add("mean clouds ms", stage_sums_.clouds * per_frame);
    status.add("icp inliers", quality_.icp_inliers);
    status.add("rgb inliers", quality_.rgb_inliers);
    status.add("condition", quality_.condition);
    status.add("fused cloud voxels", fused_map_ ? fused_map_->voxels() : 0);
    status.add("fused cloud voxels evicted (oldest first, at fused_cloud_max_voxels)", fused_map_ ? fused_map_->evictedVoxels() : 0);
  }

  // Parameters.
  std::string frame_id_, odom_frame_id_;
  bool publish_tf_ = true;
  bool skip_to_newest_ = true;  // false: every synchronised frame, in order (slow playback, parity tests)
  double wait_for_transform_ = 0.2;
  int cloud_stride_ = 4, fused_cloud_every_ = 10;
  ros::WallTimer fused_cloud_timer_;
  ros::Time fused_map_stamp_, published_fused_map_stamp_;  // of the last frame added, and of the map last published
  OdometryConfig config_;
  std::string setup_error_;
  // The finest level each frame is tracked at on a stream that skips frames (keep_pace_max_level > 0).
  std::optional<ResolutionGovernor> governor_;
  std::vector<TrackingResolution> resolutions_;  // the governor's choices, finest first

  // ROS plumbing.
  image_transport::SubscriberFilter rgb_sub_, depth_sub_;
  message_filters::Subscriber<CameraInfoMsg> info_sub_;
  std::unique_ptr<message_filters::Synchronizer<ApproximatePolicy>> approximate_;
  std::unique_ptr<message_filters::Synchronizer<ExactPolicy>> exact_;
  ros::Publisher odom_pub_, path_pub_, cloud_pub_, fused_cloud_pub_;
  ros::ServiceServer reset_service_;
  std::unique_ptr<tf2_ros::Buffer> tf_buffer_;
  std::unique_ptr<tf2_ros::TransformListener> tf_listener_;
  tf2_ros::TransformBroadcaster tf_broadcaster_;
  std::unique_ptr<diagnostic_updater::Updater> updater_;
  ros::WallTimer diagnostics_timer_, watchdog_timer_;

  // State, under mutex_ (arrival counters are atomic: they run outside the synchroniser).
  std::mutex mutex_;
  std::unique_ptr<IcpDvoOdometry> odometry_;
  std::unique_ptr<VoxelCloudMap> fused_map_;
  std::string backend_name_, last_problem_, last_degraded_, gravity_problem_;
  Eigen::Matrix3d camera_from_accelerometer_ = Eigen::Matrix3d::Identity();
  std::string camera_from_accelerometer_frame_;  // the frame camera_from_accelerometer_ is of (empty: none yet)
  double gravity_error_deg_ = -1.0;
  ros::Time last_stamp_;
  nav_msgs::Path path_;
  static constexpr std::size_t kMaxPathPoses = 4096;
  std::size_t frames_on_path_ = 0, path_stride_ = 1;
  // Further back than this is a new stream (a looped bag), nearer an out-of-order frame.
  static constexpr double kRestartAfterJumpBackSeconds = 1.0;
  // Gravity is the accelerometer's mean within this of the first frame: a hand-held camera turns little
  // in 0.2 s, and 100 samples of a 500 Hz Kinect average its noise. The first frame waits this long at
  // most for the samples after it.
  static constexpr double kGravityWindowSeconds = 0.1;
  static constexpr double kImuWaitSeconds = 0.3;
  OdometryQuality quality_;
  std::size_t frames_processed_ = 0, frames_tracked_ = 0, frames_lost_ = 0, frames_dropped_ = 0, frames_out_of_order_ = 0,
              resets_ = 0, time_jumps_back_ = 0, frames_received_at_watchdog_ = 0;
  // Tracking loss: frames_lost_ counts every frame not tracked, of which these were predicted.
  std::size_t frames_predicted_ = 0, frames_degraded_ = 0, relocalisations_ = 0, keyframes_ = 0, window_links_ = 0, window_links_skipped_ = 0;
  TrackingState state_ = TrackingState::kTracking;
  TrackingState worst_since_report_ = TrackingState::kTracking;  // lost > predicted > degraded > tracking, since the last diagnostics
  int lost_frames_ = 0, keyframe_id_ = 0;
  double processing_seconds_ = 0.0;
  StageTimes stage_sums_;
  FrameRateReport rate_report_;
  Eigen::Isometry3d odom_from_start_ = Eigen::Isometry3d::Identity();  // odom <- the base at the first frame
  std::string odom_levelling_;  // how odom was chosen, for the log and the diagnostics

  // The accelerometer (imu_topic): the last two seconds, under imu_mutex_ (it arrives on its own thread).
  std::string imu_topic_;
  ros::Subscriber imu_sub_;
  std::mutex imu_mutex_;
  std::deque<AccelerometerSample> accelerometer_;
  std::string imu_frame_;
  std::atomic<std::size_t> imu_count_{0}, imu_dropped_{0};
  // Its gyro (messages with angular velocity), under imu_mutex_; the prior built from it under mutex_.
  std::deque<ImuSample> gyro_samples_;
  ImuNoise imu_noise_;
  double imu_time_offset_ = 0.0;  // IMU stamp = camera stamp + this
  double imu_wait_ = 0.03;        // seconds a frame waits for the gyro samples past it
  std::unique_ptr<GyroRotationPrior> gyro_;
  std::size_t gyro_priors_ = 0, gyro_missing_ = 0;
  std::string gyro_problem_;

  // The newest synchronised frame and the worker that tracks it (under pending_mutex_; arrival counts
  // are atomic: they change outside both locks).
  std::mutex pending_mutex_;
  std::condition_variable pending_ready_;
  PendingFrame pending_;
  bool stopping_ = false;
  std::thread worker_;
  std::atomic<std::size_t> frames_received_{0}, frames_skipped_{0};
  std::atomic<std::size_t> rgb_count_{0}, depth_count_{0}, info_count_{0};
  StreamSilence rgb_silence_, depth_silence_, info_silence_;
  double stream_timeout_ = 5.0;  // seconds of silence on an input topic before the diagnostics name it
};

}  // namespace vocal

PLUGINLIB_EXPORT_CLASS(vocal::IcpDvoOdometryNodelet, nodelet::Nodelet)
