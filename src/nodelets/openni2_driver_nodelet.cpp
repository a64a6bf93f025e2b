// Nodelet vocal/OpenNI2Driver: RGB + depth + camera_info from a Kinect / Xtion or an .oni recording,
// with openni2_camera's topics and parameters. Streams start when someone subscribes and stop when
// the last subscriber leaves. A thin adapter over Openni2Device (ROS-free, src/driver).

#include <atomic>
#include <cstring>
#include <iomanip>
#include <memory>
#include <mutex>
#include <optional>
#include <sstream>
#include <string>

#include <camera_info_manager/camera_info_manager.h>
#include <diagnostic_updater/diagnostic_updater.h>
#include <image_transport/image_transport.h>
#include <nodelet/nodelet.h>
#include <pluginlib/class_list_macros.hpp>
#include <ros/ros.h>
#include <sensor_msgs/image_encodings.h>

#include "vocal/core/errors.h"
#include "vocal/core/stream_silence.h"
#include "vocal/driver/openni2_device.h"
#include "vocal/nodelets/message_conversions.h"

namespace vocal {

namespace {
// "640x480@30" -> mode; throws InputError naming the parameter.
Openni2VideoMode parseMode(const std::string& text, const std::string& parameter) {
  Openni2VideoMode mode;
  char x = 0, at = 0;
  std::istringstream fields(text);
  if (!(fields >> mode.width >> x >> mode.height >> at >> mode.fps) || x != 'x' || at != '@' || mode.width <= 0 ||
      mode.height <= 0 || mode.fps <= 0) {
    throw InputError("parameter " + parameter + ": '" + text + "' is not WIDTHxHEIGHT@FPS, e.g. 640x480@30");
  }
  return mode;
}
}  // namespace

class Openni2DriverNodelet : public nodelet::Nodelet {
 public:
  // Streams stop before the publishers they feed are destroyed.
  ~Openni2DriverNodelet() override {
    std::lock_guard<std::mutex> lock(mutex_);
    if (device_) {
      device_->stopColor();
      device_->stopDepth();
    }
  }

 private:
  void onInit() override {
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle& pnh = getPrivateNodeHandle();
    rgb_frame_id_ = pnh.param<std::string>("rgb_frame_id", "camera_rgb_optical_frame");
    depth_frame_id_ = pnh.param<std::string>("depth_frame_id", "camera_depth_optical_frame");
    use_device_time_ = pnh.param("use_device_time", true);
    stall_timeout_ = pnh.param("stall_timeout", 2.0);
    updater_ = std::make_unique<diagnostic_updater::Updater>(nh, pnh, getName());
    updater_->setHardwareID("vocal_openni2_driver");
    updater_->add("device", this, &Openni2DriverNodelet::diagnose);
    diagnostics_timer_ = nh.createWallTimer(ros::WallDuration(1.0), [this](const ros::WallTimerEvent&) { updater_->update(); });
    try {
      options_.device_id = pnh.param<std::string>("device_id", "");
      options_.depth_registration = pnh.param("depth_registration", true);
      options_.color_depth_synchronization = pnh.param("color_depth_synchronization", false);
      options_.color_mode = parseMode(pnh.param<std::string>("color_mode", "640x480@30"), pnh.resolveName("color_mode"));
      options_.depth_mode = parseMode(pnh.param<std::string>("depth_mode", "640x480@30"), pnh.resolveName("depth_mode"));
    } catch (const InputError& e) {
      problem_ = e.what();
      NODELET_ERROR_STREAM("OpenNI2Driver: " << problem_ << "; the nodelet stays idle");
      return;
    }
    rgb_info_url_ = pnh.param<std::string>("rgb_camera_info_url", "");
    depth_info_url_ = pnh.param<std::string>("depth_camera_info_url", "");
    // The device may be plugged in later: retry until it opens.
    open_timer_ = nh.createWallTimer(ros::WallDuration(3.0), [this](const ros::WallTimerEvent&) { openDevice(); });
    stall_timer_ = nh.createWallTimer(ros::WallDuration(0.5), [this](const ros::WallTimerEvent&) { closeIfStalled(); });
    openDevice();
  }

  void openDevice() {
    bool reopened = false;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (device_) return;
      try {
        device_ = std::make_unique<Openni2Device>(options_);
      } catch (const InputError& e) {
        if (problem_ != e.what()) NODELET_ERROR_STREAM("OpenNI2Driver: " << e.what() << "; retrying every 3 s");
        problem_ = e.what();
        return;
      }
      problem_.clear();
      open_timer_.stop();
      reopened = static_cast<bool>(rgb_info_);
      if (reopened) {
        ++reopens_;
        NODELET_INFO_STREAM("OpenNI2Driver: reopened " << device_->info().name << " (" << device_->info().uri << ")");
      } else {
        advertise();
      }
    }
    // Subscribers that were there before the device stalled want their streams back.
    if (reopened) updateStreams();
  }

  // The topics, once: a reopened device feeds the same publishers, so subscribers stay connected.
  void advertise() {
    ros::NodeHandle& nh = getNodeHandle();
    ros::NodeHandle rgb_nh(nh, "rgb"), depth_nh(nh, "depth"), registered_nh(nh, "depth_registered");
    // openni2_camera's names: rgb_<serial>, depth_<serial>; a recording's file name stands in for the serial.
    rgb_info_ = std::make_unique<camera_info_manager::CameraInfoManager>(rgb_nh, "rgb_" + device_->cameraName(), rgb_info_url_);
    depth_info_ =
        std::make_unique<camera_info_manager::CameraInfoManager>(depth_nh, "depth_" + device_->cameraName(), depth_info_url_);
    // Streams follow their subscribers (images and camera_info alike).
    auto connection = [this](const auto&) { updateStreams(); };
    image_transport::ImageTransport rgb_it(rgb_nh), depth_it(depth_nh), registered_it(registered_nh);
    rgb_pub_ = rgb_it.advertiseCamera("image_raw", 1, connection, connection, connection, connection);
    depth_pub_ = depth_it.advertiseCamera("image_raw", 1, connection, connection, connection, connection);
    registered_ = device_->registrationEnabled();
    if (registered_) {
      registered_pub_ = registered_it.advertiseCamera("image_raw", 1, connection, connection, connection, connection);
    }
    NODELET_INFO_STREAM("OpenNI2Driver: opened " << device_->info().name << " (" << device_->info().uri << ")"
                                                 << (device_->serial().empty() ? "" : ", serial " + device_->serial())
                                                 << (device_->registrationEnabled() ? ", depth registered to colour" : ""));
  }

  void updateStreams() {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!device_) return;
    const bool want_color = rgb_pub_.getNumSubscribers() > 0;
    const bool want_depth = depth_pub_.getNumSubscribers() > 0 || registered_pub_.getNumSubscribers() > 0;
    try {
      if (want_color) {
        if (!color_.on) color_.silence.arrived();  // silence counts from the start
        device_->startColor([this](const Openni2ColorFrame& frame) { publishColor(frame); });
      } else {
        device_->stopColor();
      }
      color_.on = want_color;
      if (want_depth) {
        if (!depth_.on) depth_.silence.arrived();
        device_->startDepth([this](const Openni2DepthFrame& frame) { publishDepth(frame); });
      } else {
        device_->stopDepth();
      }
      depth_.on = want_depth;
    } catch (const InputError& e) {
      problem_ = e.what();
      NODELET_ERROR_STREAM("OpenNI2Driver: " << e.what());
    }
  }

  // ROS time of a frame: the device clock moved onto ROS time at the first frame (use_device_time),
  // else the arrival time.
  ros::Time stampOf(double device_stamp) {
    const ros::Time now = ros::Time::now();
    if (!use_device_time_) return now;
    std::lock_guard<std::mutex> lock(stamp_mutex_);
    if (!have_offset_) {
      device_offset_ = now.toSec() - device_stamp;
      have_offset_ = true;
    }
    return ros::Time(device_stamp + device_offset_);
  }

  sensor_msgs::CameraInfo cameraInfo(camera_info_manager::CameraInfoManager& manager, const PinholeCamera& fallback,
                                     const std::string& frame_id, const ros::Time& stamp) {
    sensor_msgs::CameraInfo info;
    if (manager.isCalibrated()) {
      info = manager.getCameraInfo();
      if (info.width != static_cast<unsigned>(fallback.width) || info.height != static_cast<unsigned>(fallback.height)) {
        NODELET_WARN_STREAM_THROTTLE(30.0, "OpenNI2Driver: the calibration of " << frame_id << " is " << info.width << "x"
                                                                                << info.height << " but the stream is "
                                                                                << fallback.width << "x" << fallback.height
                                                                                << ": publishing the device's intrinsics");
        info = toCameraInfo(fallback, frame_id, stamp);
      }
    } else {
      info = toCameraInfo(fallback, frame_id, stamp);
    }
    info.header.stamp = stamp;
    info.header.frame_id = frame_id;
    return info;
  }

  // The device's intrinsics for a stream, asked of the device once (the modes are fixed when it opens);
  // a fallback (no field of view in the stream) is warned about then and shown in diagnostics.
  PinholeCamera deviceCamera(bool color) {
    std::lock_guard<std::mutex> lock(note_mutex_);
    std::optional<PinholeCamera>& camera = color ? color_camera_ : depth_camera_;
    if (!camera) {
      std::string& note = color ? color_intrinsics_note_ : depth_intrinsics_note_;
      camera = color ? device_->colorCamera(&note) : device_->depthCamera(&note);
      if (!note.empty()) NODELET_WARN_STREAM("OpenNI2Driver: " << note);
    }
    return *camera;
  }

  // A stream that was started and sends nothing for stall_timeout: the device was unplugged or its USB
  // bus stalled (OpenNI2 says nothing then). Close it and reopen it every 3 s, as on a late plug-in.
  void closeIfStalled() {
    std::lock_guard<std::mutex> lock(mutex_);
    if (!device_ || !(stall_timeout_ > 0.0)) return;
    for (const StreamWatch* watch : {&color_, &depth_}) {
      if (!watch->on) continue;
      const double silent = watch->silence.seconds();
      if (silent < stall_timeout_) continue;
      std::ostringstream message;
      message << device_->info().uri << ": no " << (watch == &color_ ? "colour" : "depth") << " frame for " << std::fixed
              << std::setprecision(1) << silent << " s (unplugged, or its USB bus stalled): closed, reopening every 3 s";
      problem_ = message.str();
      NODELET_ERROR_STREAM("OpenNI2Driver: " << problem_);
      ++stalls_;
      device_.reset();  // stops both streams (listeners first) and closes the device
      color_.on = depth_.on = false;
      {
        // The reopened device's clock starts again, and its modes are asked of it again.
        std::lock_guard<std::mutex> stamp_lock(stamp_mutex_);
        have_offset_ = false;
      }
      {
        std::lock_guard<std::mutex> note_lock(note_mutex_);
        color_camera_.reset(), depth_camera_.reset();
      }
      open_timer_.start();
      return;
    }
  }

  void publishColor(const Openni2ColorFrame& frame) {
    color_.silence.arrived();
    const ros::Time stamp = stampOf(frame.device_stamp);
    ++color_frames_;
    auto image = boost::make_shared<sensor_msgs::Image>(toRgb8Image(frame.image, rgb_frame_id_, stamp));
    auto info = boost::make_shared<sensor_msgs::CameraInfo>(cameraInfo(*rgb_info_, deviceCamera(true), rgb_frame_id_, stamp));
    rgb_pub_.publish(image, info);
  }

  void publishDepth(const Openni2DepthFrame& frame) {
    depth_.silence.arrived();
    const ros::Time stamp = stampOf(frame.device_stamp);
    ++depth_frames_;
    // Registered depth lies in the colour camera's frame; unregistered depth in the depth camera's.
    const bool registered = registered_;
    const std::string& frame_id = registered ? rgb_frame_id_ : depth_frame_id_;
    auto image = boost::make_shared<sensor_msgs::Image>();
    image->header.stamp = stamp;
    image->header.frame_id = frame_id;
    image->width = frame.depth.width();
    image->height = frame.depth.height();
    image->encoding = sensor_msgs::image_encodings::TYPE_16UC1;
    image->step = 2 * frame.depth.width();
    image->data.resize(static_cast<std::size_t>(image->step) * image->height);
    std::memcpy(image->data.data(), frame.depth.data(), image->data.size());
    auto info = boost::make_shared<sensor_msgs::CameraInfo>(cameraInfo(*depth_info_, deviceCamera(false), frame_id, stamp));
    if (registered && registered_pub_.getNumSubscribers() > 0) registered_pub_.publish(image, info);
    if (depth_pub_.getNumSubscribers() > 0) depth_pub_.publish(image, info);
  }

  void diagnose(diagnostic_updater::DiagnosticStatusWrapper& status) {
    std::lock_guard<std::mutex> lock(mutex_);
    using diagnostic_msgs::DiagnosticStatus;
    if (!problem_.empty()) {
      status.summary(DiagnosticStatus::ERROR, problem_);
    } else if (!device_) {
      status.summary(DiagnosticStatus::WARN, "no device opened yet");
    } else {
      status.summary(DiagnosticStatus::OK, "streaming on demand");
      status.add("uri", device_->info().uri);
      status.add("serial", device_->serial());
      status.add("depth registration", device_->registrationEnabled());
    }
    status.add("colour frames", color_frames_.load());
    status.add("depth frames", depth_frames_.load());
    status.add("stalls (no frame for stall_timeout)", stalls_);
    status.add("reopened after a stall", reopens_);
    std::lock_guard<std::mutex> note_lock(note_mutex_);
    if (!color_intrinsics_note_.empty()) status.add("colour intrinsics", color_intrinsics_note_);
    if (!depth_intrinsics_note_.empty()) status.add("depth intrinsics", depth_intrinsics_note_);
    if (!color_intrinsics_note_.empty() || !depth_intrinsics_note_.empty()) {
      if (status.level == DiagnosticStatus::OK) status.summary(DiagnosticStatus::WARN, "nominal or borrowed intrinsics: see below");
    }
  }

  Openni2Options options_;
  std::string rgb_frame_id_, depth_frame_id_, rgb_info_url_, depth_info_url_, problem_;
  bool use_device_time_ = true;
  bool registered_ = false;  // depth registered to colour: asked of the device when first opened
  std::mutex mutex_, stamp_mutex_, note_mutex_;
  std::optional<PinholeCamera> color_camera_, depth_camera_;  // under note_mutex_, once known
  std::string color_intrinsics_note_, depth_intrinsics_note_;  // why a stream's intrinsics are a fallback
  std::unique_ptr<Openni2Device> device_;
  std::unique_ptr<camera_info_manager::CameraInfoManager> rgb_info_, depth_info_;
  image_transport::CameraPublisher rgb_pub_, depth_pub_, registered_pub_;
  std::unique_ptr<diagnostic_updater::Updater> updater_;
  ros::WallTimer diagnostics_timer_, open_timer_, stall_timer_;
  double stall_timeout_ = 2.0;  // seconds without a frame on a started stream
  struct StreamWatch {
    bool on = false;        // started, under mutex_
    StreamSilence silence;  // since it was started or its last frame (marked by OpenNI2's frame thread)
  };
  StreamWatch color_, depth_;
  std::size_t stalls_ = 0, reopens_ = 0;  // under mutex_
  bool have_offset_ = false;
  double device_offset_ = 0.0;
  std::atomic<std::size_t> color_frames_{0}, depth_frames_{0};
};

}  // namespace vocal

PLUGINLIB_EXPORT_CLASS(vocal::Openni2DriverNodelet, nodelet::Nodelet)
