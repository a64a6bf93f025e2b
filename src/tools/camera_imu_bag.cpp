#include "vocal/tools/camera_imu_bag.h"

#include <algorithm>
#include <deque>
#include <future>
#include <optional>
#include <sstream>

#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/CompressedImage.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/Imu.h>

#include "vocal/calibration/extraction/pattern_observation.h"
#include "vocal/core/errors.h"
#include "vocal/core/worker_pool.h"
#include "vocal/nodelets/message_conversions.h"
#include "vocal/simulation/rig_simulator.h"
#include "vocal/simulation/simulated_sensor_data.h"
#include "vocal/tools/bag_file.h"

namespace vocal {

CameraImuRecording readCameraImuBag(const std::string& bag_path, const RigDescription& rig, int imu_index, int threads) {
  const RigImuDescription& imu = rig.imus.at(imu_index);
  const RigSensorDescription& camera = rig.sensors.at(imu.camera);
  if (threads < 0) throw InputError("camera-IMU bag reading: threads must be >= 0 (0 = the cores), got " + std::to_string(threads));
  if (threads == 0) threads = defaultThreadCount();
  rosbag::Bag bag;
  openBag(&bag, bag_path, rosbag::bagmode::Read);
  CameraImuRecording out;
  const auto drop = [&](const std::string& topic, const ros::Time& time, const std::string& why) {
    if (out.problems.size() < 10) {
      std::ostringstream problem;
      problem << topic << " at " << time << ": " << why;
      out.problems.push_back(problem.str());
    }
    ++out.dropped;
  };
  try {
    if (!firstUsableCameraInfo(bag, camera.camera_info_topic, &out.camera, &out.lens)) {
      throw InputError(bag_path + ": no usable camera_info on " + camera.camera_info_topic + " for camera '" + camera.spec.name + "'");
    }
    // The board searched a few frames ahead on every core; each frame decoded on the thread that searches it.
    struct Pending {
      double stamp;
      ros::Time time;
      std::future<std::optional<CameraImuView>> board;
    };
    std::deque<Pending> pending;
    const auto takeOldest = [&] {
      Pending oldest = std::move(pending.front());
      pending.pop_front();
      try {
        if (std::optional<CameraImuView> view = oldest.board.get()) {
          view->stamp = oldest.stamp;
          out.views.push_back(std::move(*view));
        }
      } catch (const InputError& e) {
        drop(camera.image_topic, oldest.time, e.what());
      }
    };
    const std::launch launch = threads == 1 ? std::launch::deferred : std::launch::async;
    const TargetPattern pattern = rig.target.pattern;
    rosbag::View view(bag, rosbag::TopicQuery(std::vector<std::string>{camera.image_topic, imu.imu_topic}));
    for (const rosbag::MessageInstance& m : view) {
      if (m.getTopic() == imu.imu_topic) {
        ++out.imu_messages;
        try {
          const auto msg = m.instantiate<sensor_msgs::Imu>();
          if (!msg) throw InputError(m.getTopic() + ": not a sensor_msgs/Imu");
          if (msg->angular_velocity_covariance[0] == -1.0) throw InputError("the message has no angular velocity (covariance -1): a gyro is needed");
          ImuSample sample = fromImuMessage(*msg, m.getTopic());
          out.imu.push_back(sample);
        } catch (const InputError& e) {
          drop(m.getTopic(), m.getTime(), e.what());
        }
        continue;
      }
      ++out.images;
      const auto compressed = m.instantiate<sensor_msgs::CompressedImage>();
      const auto raw = compressed ? nullptr : m.instantiate<sensor_msgs::Image>();
      if (!compressed && !raw) {
        drop(m.getTopic(), m.getTime(), "not a sensor_msgs/Image or CompressedImage");
        continue;
      }
      const double stamp = (compressed ? compressed->header.stamp : raw->header.stamp).toSec();
      pending.push_back({stamp, m.getTime(), std::async(launch, [compressed, raw, topic = m.getTopic(), &pattern, &out, name = camera.spec.name]
                                                           () -> std::optional<CameraImuView> {
        const ColorImage image = compressed ? fromCompressedColorImage(*compressed, topic) : fromColorImage(*raw, topic);
        if (image.width() != out.camera.width || image.height() != out.camera.height) {
          throw InputError("the image is " + std::to_string(image.width()) + "x" + std::to_string(image.height()) + ", its camera_info " +
                           std::to_string(out.camera.width) + "x" + std::to_string(out.camera.height));
        }
        std::vector<Eigen::Vector2d> corners;
        try {
          corners = detectPattern(image, pattern, name.c_str());
        } catch (const InputError&) {
          return std::nullopt;  // the board out of view or blurred: a waved session has such frames
        }
        const PatternObservation seen = observePattern(corners, pattern, out.camera, name.c_str(), out.lens);
        return cameraImuView(0.0, seen, std::move(corners));
      })});
      while (pending.size() > static_cast<std::size_t>(threads)) takeOldest();
    }
    while (!pending.empty()) takeOldest();
  } catch (const rosbag::BagException& e) {
    throw InputError(bag_path + ": read failed (" + e.what() + ")");
  }
  if (out.images == 0) throw InputError(bag_path + ": no image of camera '" + camera.spec.name + "' on " + camera.image_topic);
  if (out.imu.empty()) throw InputError(bag_path + ": no sensor_msgs/Imu of imu '" + imu.name + "' on " + imu.imu_topic);
  // By stamp; a repeated or backwards IMU stamp (a driver's) is dropped, counted.
  const auto by_stamp = [](const auto& a, const auto& b) { return a.stamp < b.stamp; };
  std::stable_sort(out.views.begin(), out.views.end(), by_stamp);
  std::stable_sort(out.imu.begin(), out.imu.end(), by_stamp);
  const auto repeated = [](const auto& a, const auto& b) { return !(a.stamp < b.stamp); };
  const std::size_t imu_before = out.imu.size(), views_before = out.views.size();
  out.imu.erase(std::unique(out.imu.begin(), out.imu.end(), repeated), out.imu.end());
  out.views.erase(std::unique(out.views.begin(), out.views.end(), repeated), out.views.end());
  const std::size_t repeats = imu_before - out.imu.size() + views_before - out.views.size();
  if (repeats > 0) {
    out.dropped += repeats;
    out.problems.push_back(std::to_string(repeats) + " messages with a stamp repeated (IMU or camera): dropped");
  }
  return out;
}

RigDescription simulatedCameraImuRig(const WavedCameraImuOptions& options, const Eigen::Isometry3d& camera_in_rig, bool compressed,
                                     const std::string& camera_name) {
  RigDescription rig;
  rig.reference_frame = "base_link";
  rig.target.pattern = options.pattern;
  rig.target.width = (options.pattern.cols + 1) * options.pattern.square_size + 0.1;
  rig.target.height = (options.pattern.rows + 1) * options.pattern.square_size + 0.1;
  RigSensorDescription camera;
  camera.spec = {camera_name, SensorType::kCamera, camera_name + "_optical_frame"};
  camera.image_topic = "/" + camera_name + (compressed ? "/image_raw/compressed" : "/image_raw");
  camera.camera_info_topic = "/" + camera_name + "/camera_info";
  camera.pose = camera_in_rig;
  rig.sensors.push_back(camera);
  RigImuDescription imu;
  imu.name = "imu";
  imu.frame_id = "imu_link";
  imu.imu_topic = "/imu/data";
  imu.camera = 0;
  imu.noise = options.noise;
  rig.imus.push_back(imu);
  rig.reference_sensor = 0;
  return rig;
}

void writeSimulatedWavedBag(const WavedCameraImuSession& session, const WavedCameraImuOptions& options, const RigDescription& rig,
                            const std::string& path, int threads) {
  const RigImuDescription& imu = rig.imus.at(0);
  const RigSensorDescription& camera = rig.sensors.at(imu.camera);
  if (threads <= 0) threads = defaultThreadCount();
  const bool compressed = isCompressedImageTopic(camera.image_topic);
  // The room's frame: the board 2 m ahead of its origin, 1.1 m up, facing it (as the still-pose sessions have it).
  Eigen::Isometry3d room_from_board = Eigen::Isometry3d::Identity();
  room_from_board.translation() = Eigen::Vector3d(2.0, 0.0, 1.1);
  room_from_board.linear() = targetFacingRig();
  const CameraRays rays(options.camera, options.lens);
  const double base = 1000.0;
  rosbag::Bag bag;
  openBag(&bag, path, rosbag::bagmode::Write);
  try {
    std::size_t next_imu = 0;
    const auto writeImuUntil = [&](double stamp) {
      for (; next_imu < session.imu.size() && session.imu[next_imu].stamp <= stamp; ++next_imu) {
        ImuSample sample = session.imu[next_imu];
        sample.stamp += base;
        const ros::Time time(sample.stamp);
        bag.write(imu.imu_topic, time, toImuMessage(sample, imu.frame_id));
      }
    };
    const std::size_t frames = session.frame_stamps.size();
    for (std::size_t first = 0; first < frames; first += threads) {
      std::vector<std::future<ColorImage>> rendered;
      for (std::size_t k = first; k < std::min(frames, first + threads); ++k) {
        rendered.push_back(std::async(std::launch::async, [&, k] {
          SimulatedSensor sensor{camera.spec, room_from_board * session.board_from_camera[k]};
          SimulatedRoomView view;
          view.sensor = &sensor;
          view.target = &rig.target;
          view.reference_from_target = room_from_board;
          std::mt19937 rng(options.seed * 100003u + static_cast<std::uint32_t>(k));
          return simulateCameraImage(view, rays, 2.0, &rng);
        }));
      }
      for (std::size_t k = first; k < std::min(frames, first + threads); ++k) {
        const double stamp = base + session.frame_stamps[k];
        writeImuUntil(stamp);
        const ros::Time time(stamp);
        const ColorImage image = rendered[k - first].get();
        if (compressed) {
          bag.write(camera.image_topic, time, toCompressedJpeg(image, camera.spec.frame_id, time));
        } else {
          bag.write(camera.image_topic, time, toMono8Image(image, camera.spec.frame_id, time));
        }
        bag.write(camera.camera_info_topic, time, toCameraInfo(options.camera, camera.spec.frame_id, time, options.lens));
      }
    }
    writeImuUntil(1e300);
  } catch (const rosbag::BagException& e) {
    throw InputError(path + ": write failed (" + e.what() + ")");
  }
  bag.close();
}

}  // namespace vocal
