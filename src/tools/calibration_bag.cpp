#include "vocal/tools/calibration_bag.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <deque>
#include <future>
#include <map>
#include <memory>
#include <random>
#include <sstream>

#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/JointState.h>

#include "vocal/core/errors.h"
#include "vocal/core/se3.h"
#include "vocal/core/worker_pool.h"
#include "vocal/nodelets/message_conversions.h"
#include "vocal/simulation/simulated_sensor_data.h"
#include "vocal/tools/bag_file.h"

namespace vocal {

RigDescription describeSimulatedRig(const std::vector<SimulatedSensor>& sensors, const TargetDescription& target,
                                    bool with_all_poses) {
  RigDescription rig;
  rig.reference_frame = "base_link";
  rig.target = target;
  for (std::size_t i = 0; i < sensors.size(); ++i) {
    RigSensorDescription d;
    d.spec = sensors[i].spec;
    const std::string prefix = "/" + d.spec.name;
    switch (d.spec.type) {
      case SensorType::kCamera:
        d.image_topic = prefix + "/image_raw", d.camera_info_topic = prefix + "/camera_info";
        break;
      case SensorType::kRgbd:
        d.depth_topic = prefix + "/depth/image_raw", d.camera_info_topic = prefix + "/depth/camera_info";
        break;
      case SensorType::kLidar3d:
        d.cloud_topic = prefix + "/points";
        break;
      case SensorType::kLaser2d:
        d.scan_topic = prefix + "/scan";
        break;
    }
    if (with_all_poses || i == 0) d.pose = sensors[i].reference_from_sensor;
    rig.sensors.push_back(d);
  }
  rig.reference_sensor = 0;
  return rig;
}

SimulatedSensorFault parseSimulatedSensorFault(const std::string& text, const std::vector<SimulatedSensor>& sensors, const std::string& what) {
  const std::size_t first = text.find(':'), second = first == std::string::npos ? first : text.find(':', first + 1);
  const std::string usage = what + ": '" + text + "': expected KIND:SENSOR:AMOUNT, KIND one of moves, bumped, time-offset, focal";
  if (second == std::string::npos) throw InputError(usage);
  const std::string kind = text.substr(0, first), name = text.substr(first + 1, second - first - 1), amount = text.substr(second + 1);
  SimulatedSensorFault fault;
  if (kind == "moves") fault.kind = SimulatedSensorFault::Kind::kMoves;
  else if (kind == "bumped") fault.kind = SimulatedSensorFault::Kind::kBumped;
  else if (kind == "time-offset") fault.kind = SimulatedSensorFault::Kind::kTimeOffset;
  else if (kind == "focal") fault.kind = SimulatedSensorFault::Kind::kFocalScale;
  else throw InputError(usage);
  fault.sensor = -1;
  for (std::size_t s = 0; s < sensors.size(); ++s)
    if (sensors[s].spec.name == name) fault.sensor = static_cast<int>(s);
  if (fault.sensor < 0) throw InputError(what + ": '" + text + "': the rig has no sensor '" + name + "'");
  char* end = nullptr;
  fault.amount = std::strtod(amount.c_str(), &end);
  if (amount.empty() || *end != '\0' || !std::isfinite(fault.amount)) throw InputError(usage);
  if (fault.kind == SimulatedSensorFault::Kind::kFocalScale && (sensors[fault.sensor].spec.type != SensorType::kCamera || !(fault.amount > 0.0))) {
    throw InputError(what + ": '" + text + "': a focal scale applies to a camera and must be > 0");
  }
  return fault;
}

Eigen::Isometry3d faultyPlacement(const Eigen::Isometry3d& as_built, const std::vector<SimulatedSensorFault>& faults, int sensor_index,
                                  int k, int poses, std::uint32_t seed) {
  Eigen::Isometry3d placed = as_built;
  for (const SimulatedSensorFault& fault : faults) {
    if (fault.sensor != sensor_index) continue;
    if (fault.kind == SimulatedSensorFault::Kind::kMoves) {
      // A pan-tilt head: pan about the sensor's y (optical frames: down) and tilt about its x, about a
      // pivot 8 cm behind it; a new draw per pose, the same for every message of the pose.
      std::mt19937 rng(seed * 7919u + static_cast<std::uint32_t>(k) * 104729u + static_cast<std::uint32_t>(sensor_index));
      std::uniform_real_distribution<double> turn(-fault.amount, fault.amount);
      const Eigen::Vector3d pivot(0.0, 0.0, -0.08);
      const Eigen::Matrix3d head = (Eigen::AngleAxisd(turn(rng), Eigen::Vector3d::UnitY()) *
                                    Eigen::AngleAxisd(0.5 * turn(rng), Eigen::Vector3d::UnitX())).toRotationMatrix();
      Eigen::Isometry3d motion = Eigen::Isometry3d::Identity();
      motion.linear() = head;
      motion.translation() = pivot - head * pivot;
      placed = placed * motion;
    } else if (fault.kind == SimulatedSensorFault::Kind::kBumped && 2 * k >= poses) {
      Eigen::Isometry3d bump = Eigen::Isometry3d::Identity();
      bump.linear() = Eigen::AngleAxisd(fault.amount, Eigen::Vector3d(1.0, 1.0, 0.0).normalized()).toRotationMatrix();
      bump.translation() = fault.amount * Eigen::Vector3d(1.0, -1.0, 1.0).normalized();
      placed = placed * bump;
    }
  }
  return placed;
}

namespace {
// Keeps the returns (sensor frame) within `radius` of any still pose's board centre.
void cropAroundBoards(std::vector<Eigen::Vector3d>* cloud, std::vector<int>* rings, const Eigen::Isometry3d& rig_from_sensor,
                      const std::vector<Eigen::Isometry3d>& boards, double radius) {
  std::size_t kept = 0;
  for (std::size_t i = 0; i < cloud->size(); ++i) {
    const Eigen::Vector3d p = rig_from_sensor * (*cloud)[i];
    bool near = false;
    for (const Eigen::Isometry3d& board : boards) near = near || (p - board.translation()).norm() <= radius;
    if (!near) continue;
    (*cloud)[kept] = (*cloud)[i];
    if (i < rings->size()) (*rings)[kept] = (*rings)[i];
    ++kept;
  }
  cloud->resize(kept);
  if (rings->size() > kept) rings->resize(kept);
}

double faultAmount(const std::vector<SimulatedSensorFault>& faults, int sensor_index, SimulatedSensorFault::Kind kind, double none) {
  for (const SimulatedSensorFault& fault : faults)
    if (fault.sensor == sensor_index && fault.kind == kind) return fault.amount;
  return none;
}
}  // namespace

std::vector<SimulatedSensor> panTiltRig(bool head_laser) {
  std::vector<SimulatedSensor> sensors = exampleRig(0, 1, 1, 0);
  if (head_laser) {
    // Its x along the link's (the camera's line of sight), 5 cm under the camera, rolled 0.12 rad: its line
    // crosses the board at a slant wherever the head aims.
    SimulatedSensor& laser = sensors[1];
    laser.spec = {"head_laser", SensorType::kLaser2d, "head_laser"};
    laser.reference_from_sensor.linear() = rotationFromRollPitchYaw(0.12, 0.01, -0.02);
    laser.reference_from_sensor.translation() = Eigen::Vector3d(0.05, 0.0, -0.02);
  }
  SimulatedSensor camera;
  camera.spec = {"head_camera", SensorType::kRgbd, "head_camera_depth_optical_frame"};
  camera.reference_from_sensor.linear() = rotationFromRollPitchYaw(0.01, -0.02, 0.015) * bodyFromOpticalRotation();
  camera.reference_from_sensor.translation() = Eigen::Vector3d(0.06, 0.01, 0.03);
  sensors.push_back(camera);
  return sensors;
}

void putOnPanTiltHead(const std::vector<SimulatedSensor>& sensors, SimulatedSessionOptions* options, RigDescription* rig,
                      RigDescription* truth, bool pose_known, const Eigen::Vector3d& tilt_origin_error, bool head_laser) {
  const int camera = static_cast<int>(sensors.size()) - 1;
  SimulatedPanTiltOptions head_options;
  head_options.seed = options->seed;
  head_options.wander = 0.3;  // both joints sweep: the offsets before the camera's mount are told from it
  head_options.tilt_origin_error = tilt_origin_error;
  options->head = simulatePanTilt(simulatedStillPoses(*options, rig->target), sensors[camera].reference_from_sensor, head_options);
  options->head_sensors = {camera};
  for (std::size_t s = 0; head_laser && s < sensors.size(); ++s)
    if (sensors[s].spec.type == SensorType::kLaser2d) options->head_sensors.push_back(static_cast<int>(s));
  rig->joints = truth->joints = options->head->joints;
  for (JointDescription& joint : rig->joints) joint.offset = 0.0;  // the unknowns
  rig->joints.back().origin.translation() -= tilt_origin_error;  // the model's
  for (const int s : options->head_sensors) {
    rig->sensors[s].parent = truth->sensors[s].parent = options->head->joints.back().child;
    truth->sensors[s].pose = sensors[s].reference_from_sensor;
  }
  if (pose_known) rig->sensors[camera].pose = sensors[camera].reference_from_sensor, rig->sensors[camera].pose_known = true;
}

std::vector<Eigen::Isometry3d> simulatedStillPoses(const SimulatedSessionOptions& options, const TargetDescription& target) {
  RigSimulationOptions poses;
  poses.target_poses = options.target_poses;
  poses.seed = options.seed;
  poses.turn_range = options.turn_range;
  poses.target_width = target.width;
  poses.target_height = target.height;
  return simulateRig(std::vector<SimulatedSensor>{}, poses).reference_from_target;
}

SimulatedSessionSummary writeSimulatedCalibrationBag(const std::vector<SimulatedSensor>& sensors, const RigDescription& rig,
                                                     const SimulatedSessionOptions& options, const std::string& bag_path) {
  // Each sensor's rate and the timeline, checked before anything is written.
  std::vector<double> rates;
  for (const SimulatedSensor& sensor : sensors) {
    const SensorType type = sensor.spec.type;
    const double own = type == SensorType::kCamera ? options.camera_rate
                       : type == SensorType::kRgbd ? options.rgbd_rate
                       : type == SensorType::kLidar3d ? options.lidar_rate
                                                      : options.laser_rate;
    rates.push_back(own > 0.0 ? own : options.rate);
    if (!(rates.back() > 0.0)) throw InputError("simulated session: sensor '" + sensor.spec.name + "' has no positive rate");
  }
  if (!(options.still_seconds > 0.0 && options.moving_seconds >= 0.0)) {
    throw InputError("simulated session: the still time must be > 0 s and the moving time >= 0 s");
  }
  rosbag::Bag bag;
  openBag(&bag, bag_path, rosbag::bagmode::Write);
  SimulatedSessionSummary summary;
  summary.reference_from_target = simulatedStillPoses(options, rig.target);
  bool on_rig = !options.head_sensors.empty();
  for (const int s : options.head_sensors) on_rig = on_rig && s >= 0 && s < static_cast<int>(sensors.size());
  if (options.head && (!on_rig || options.head->angles.size() != summary.reference_from_target.size())) {
    throw InputError("simulated session: the pan-tilt head names no sensor of the rig, or not one aim per still pose");
  }

  std::mt19937 rng(options.seed);
  const int rings = options.lidar_model == LidarModel::kOuster64 ? 64 : options.lidar_model == LidarModel::kScanner ? 77 : 16;
  std::vector<double> ring_bias(rings, 0.0);
  if (options.ring_bias > 0.0) {
    std::uniform_real_distribution<double> bias(-options.ring_bias, options.ring_bias);
    for (double& b : ring_bias) b = bias(rng);
  }
  for (double& b : ring_bias) b += options.lidar_range_offset;
  // The session's lenses, each undistorted once (most of a distorted render's cost), and camera i's.
  const PinholeCamera image_camera = defaultKinectCamera(640, 480);
  const std::vector<LensDistortion> lenses = options.camera_lenses.empty() ? std::vector<LensDistortion>(1) : options.camera_lenses;
  std::vector<CameraRays> rays;
  for (const LensDistortion& lens : lenses) rays.emplace_back(image_camera, lens);
  std::vector<std::size_t> lens_of(sensors.size(), 0);
  for (std::size_t s = 0, camera = 0; s < sensors.size(); ++s)
    if (sensors[s].spec.type == SensorType::kCamera) lens_of[s] = camera++ % lenses.size();
  const PinholeCamera depth_camera = defaultKinectCamera(options.depth_width, options.depth_height);
  // Every message in time order: sensor s publishes at 0.013 s * s + i / rate.
  const double pose_seconds = options.still_seconds + options.moving_seconds;
  const double duration = options.target_poses * pose_seconds;
  std::vector<std::pair<double, std::size_t>> messages;
  for (std::size_t s = 0; s < sensors.size(); ++s)
    for (int i = 0; 0.013 * s + i / rates[s] < duration - 1e-9; ++i) messages.emplace_back(0.013 * s + i / rates[s], s);
  // The head's joint states: index sensors.size().
  const std::size_t joint_states = sensors.size();
  for (int i = 0; options.head && i / options.joint_state_rate < duration - 1e-9; ++i) messages.emplace_back(i / options.joint_state_rate, joint_states);
  std::sort(messages.begin(), messages.end());
  std::vector<int> joint_direction(options.head ? options.head->joints.size() : 0, 0);  // of each joint's last motion (backlash)
  std::vector<double> last_angles;
  try {
    for (const auto& [time, s] : messages) {
      if (s == joint_states) {
        const std::vector<double> angles = options.head->anglesAt(time, options.still_seconds, options.moving_seconds);
        for (std::size_t j = 0; j < angles.size() && !last_angles.empty(); ++j)
          if (std::abs(angles[j] - last_angles[j]) > 1e-9) joint_direction[j] = angles[j] > last_angles[j] ? 1 : -1;
        last_angles = angles;
        sensor_msgs::JointState state;
        state.header.stamp = ros::Time(1000.0 + time);
        for (const JointDescription& joint : options.head->joints) state.name.push_back(joint.name);
        state.position = options.head->reported(angles, joint_direction);
        bag.write(options.joint_states_topic, state.header.stamp, state);
        ++summary.messages;
        continue;
      }
      const int k = std::min(options.target_poses - 1, static_cast<int>(time / pose_seconds));
      const double into_pose = time - k * pose_seconds;
      const double alpha = into_pose < options.still_seconds ? 0.0 : (into_pose - options.still_seconds) / options.moving_seconds;
      SimulatedRoomView view;
      view.reference_from_target = interpolatePose(summary.reference_from_target[k],
                                                   summary.reference_from_target[(k + 1) % options.target_poses], alpha);
      view.target = &rig.target;
      view.layout = options.room;
      view.person_holds_target = options.person_holds_target;
      view.mixed_pixels = options.mixed_pixels;
      const bool lidar = sensors[s].spec.type == SensorType::kLidar3d;
      const bool laser = sensors[s].spec.type == SensorType::kLaser2d;
      view.range_noise = lidar && options.lidar_noise >= 0.0   ? options.lidar_noise
                         : laser && options.laser_noise >= 0.0 ? options.laser_noise
                                                               : options.range_noise;
      view.ring_bias = lidar ? ring_bias : std::vector<double>{};
      view.beam_aperture = laser ? options.laser_beam_aperture : 0.0;
      view.beam_divergence = laser ? options.laser_beam_divergence : 0.0;
      view.lidar_model = options.lidar_model;
      if (options.lidar_vertical_offsets && options.lidar_model == LidarModel::kVlp16) view.ring_height = kVlp16VerticalOffsets;
      view.dark_range_offset = lidar ? options.dark_range_offset : 0.0;
      view.dark_absorbs = lidar && options.dark_absorbs;
      // As an Ouster driver publishes it: organised, its misses at the origin (fromPointCloud2 drops them).
      view.no_returns_at_origin = lidar && options.lidar_model == LidarModel::kOuster64 && options.lidar_crop <= 0.0;
      view.board_on_stand = options.board_on_stand;
      view.time = time;
      SimulatedSensor placed = sensors[s];
      placed.reference_from_sensor = faultyPlacement(sensors[s].reference_from_sensor, options.faults, static_cast<int>(s), k, options.target_poses, options.seed);
      if (options.head && std::count(options.head_sensors.begin(), options.head_sensors.end(), static_cast<int>(s))) {
        placed.reference_from_sensor = options.head->baseFromSensor(options.head->anglesAt(time, options.still_seconds, options.moving_seconds),
                                                                    sensors[s].reference_from_sensor);
      }
      view.sensor = &placed;
      const RigSensorDescription& d = rig.sensors[s];
      const ros::Time stamp(1000.0 + time + faultAmount(options.faults, static_cast<int>(s), SimulatedSensorFault::Kind::kTimeOffset, 0.0));
      switch (d.spec.type) {
        case SensorType::kCamera:
        {
          PinholeCamera told = image_camera;  // what camera_info says: wrong with a focal-scale fault
          const double scale = faultAmount(options.faults, static_cast<int>(s), SimulatedSensorFault::Kind::kFocalScale, 1.0);
          told.fx *= scale, told.fy *= scale;
          bag.write(d.camera_info_topic, stamp, toCameraInfo(told, d.spec.frame_id, stamp, lenses[lens_of[s]]));
        }
          bag.write(d.image_topic, stamp, toMono8Image(simulateCameraImage(view, rays[lens_of[s]], options.image_noise, &rng), d.spec.frame_id, stamp));
          summary.messages += 2;
          break;
        case SensorType::kRgbd:
          bag.write(d.camera_info_topic, stamp, toCameraInfo(depth_camera, d.spec.frame_id, stamp));
          bag.write(d.depth_topic, stamp, toDepth32FImage(simulateDepthImage(view, depth_camera, &rng), d.spec.frame_id, stamp));
          summary.messages += 2;
          break;
        case SensorType::kLidar3d: {
          SimulatedTruth truth;
          std::vector<Eigen::Vector3d> cloud = simulateLidarCloud(view, &rng, &truth);
          if (options.lidar_crop > 0.0) cropAroundBoards(&cloud, &truth.rings, placed.reference_from_sensor, summary.reference_from_target,
                                                         options.lidar_crop);
          // A scanner's driver publishes no ring field.
          if (options.lidar_model == LidarModel::kScanner) truth.rings.clear();
          bag.write(d.cloud_topic, stamp, toLidarPointCloud2(cloud, truth.rings, d.spec.frame_id, stamp));
          ++summary.messages;
          break;
        }
        case SensorType::kLaser2d:
          bag.write(d.scan_topic, stamp,
                    toLaserScan(simulateLaserRanges(view, &rng), -135.0 * M_PI / 180.0, 0.25 * M_PI / 180.0, 8.0, d.spec.frame_id, stamp));
          ++summary.messages;
          break;
      }
    }
  } catch (const rosbag::BagException& e) {
    throw InputError(bag_path + ": write failed (" + e.what() + ")");
  }
  bag.close();
  return summary;
}


BagReadSummary readCalibrationBag(const std::string& bag_path, CalibrationSession* session,
                                  const std::function<void(std::size_t)>& progress, int threads) {
  rosbag::Bag bag;
  openBag(&bag, bag_path, rosbag::bagmode::Read);
  const RigDescription& rig = session->rig();
  // Topic -> (sensor, what arrives there).
  enum class Kind { kImage, kInfo, kDepth, kCloud, kScan, kJointState };
  std::map<std::string, std::vector<std::pair<int, Kind>>> routes;
  for (std::size_t s = 0; s < rig.sensors.size(); ++s) {
    const RigSensorDescription& d = rig.sensors[s];
    const int i = static_cast<int>(s);
    if (d.spec.type == SensorType::kCamera) routes[d.image_topic].push_back({i, Kind::kImage});
    if (d.spec.type == SensorType::kRgbd) routes[d.depth_topic].push_back({i, Kind::kDepth});
    if (d.spec.type == SensorType::kCamera || d.spec.type == SensorType::kRgbd) routes[d.camera_info_topic].push_back({i, Kind::kInfo});
    if (d.spec.type == SensorType::kLidar3d) routes[d.cloud_topic].push_back({i, Kind::kCloud});
    if (d.spec.type == SensorType::kLaser2d) routes[d.scan_topic].push_back({i, Kind::kScan});
  }
  // The joints' positions, when a sensor is behind joints (not a sensor's: index -1).
  if (rig.needsJointStates()) routes[rig.joint_states_topic].push_back({-1, Kind::kJointState});
  std::vector<std::string> topics;
  for (const auto& route : routes) topics.push_back(route.first);

  BagReadSummary summary;
  std::map<int, PinholeCamera> cameras;  // latest camera_info per sensor
  std::map<int, LensDistortion> lenses;   // ... and its distortion
  try {
    // A camera_info stamped like its image may be stored after it: start from each sensor's first one.
    for (const auto& route : routes) {
      for (const auto& [sensor, kind] : route.second) {
        if (kind != Kind::kInfo || cameras.count(sensor)) continue;
        PinholeCamera camera;
        LensDistortion lens;
        if (firstUsableCameraInfo(bag, route.first, &camera, &lens)) cameras[sensor] = camera, lenses[sensor] = lens;
      }
    }
    rosbag::View view(bag, rosbag::TopicQuery(topics));
    if (view.size() == 0) {
      std::string list;
      for (const std::string& t : topics) list += (list.empty() ? "" : ", ") + t;
      throw InputError(bag_path + ": holds none of the rig's topics (" + list + ")");
    }
    // The target searched on every core a few messages ahead of the session, which takes each result in
    // bag order (the static background, the still runs and the ring offsets depend on it).
    struct Pending {
      int sensor;
      double stamp;
      std::string topic;  // and bag time: where a dropped message was
      ros::Time time;
      std::future<CalibrationSession::Extraction> extraction;
    };
    std::deque<Pending> pending;
    if (threads < 0) throw InputError("calibration bag reading: threads must be >= 0 (0 = the cores), got " + std::to_string(threads));
    if (threads == 0) threads = defaultThreadCount();
    const std::size_t ahead = static_cast<std::size_t>(threads);
    // One thread: each search runs on this thread when its result is taken.
    const std::launch launch = threads == 1 ? std::launch::deferred : std::launch::async;
    const auto drop = [&](const std::string& topic, const ros::Time& time, const std::string& why) {
      if (summary.problems.size() < 20) {
        std::ostringstream problem;
        problem << topic << " at " << time << ": " << why;
        summary.problems.push_back(problem.str());
      }
      ++summary.dropped;
    };
    const auto takeOldest = [&] {
      Pending oldest = std::move(pending.front());
      pending.pop_front();
      try {
        session->take(oldest.sensor, oldest.stamp, oldest.extraction.get());
      } catch (const InputError& e) {
        drop(oldest.topic, oldest.time, e.what());
      }
    };
    for (const rosbag::MessageInstance& m : view) {
      ++summary.messages;
      if (progress) progress(summary.messages);
      for (const auto& [sensor, kind] : routes.at(m.getTopic())) {
        if (kind == Kind::kJointState) {
          try {
            const auto state = m.instantiate<sensor_msgs::JointState>();
            if (!state) throw InputError(m.getTopic() + ": not a sensor_msgs/JointState");
            // Stamped by the driver; an unstamped one (some publish 0) at its recording time.
            const double stamp = state->header.stamp.isZero() ? m.getTime().toSec() : state->header.stamp.toSec();
            session->addJointState(stamp, state->name, state->position);
          } catch (const InputError& e) {
            drop(m.getTopic(), m.getTime(), e.what());
          }
          continue;
        }
        const std::string& name = rig.sensors[sensor].spec.name;
        try {
          std::future<CalibrationSession::Extraction> extraction;
          switch (kind) {
            case Kind::kInfo: {
              const auto info = m.instantiate<sensor_msgs::CameraInfo>();
              if (!info) throw InputError(m.getTopic() + ": not a sensor_msgs/CameraInfo");
              cameras[sensor] = fromCameraInfo(*info, m.getTopic());
              lenses[sensor] = lensDistortionFromCameraInfo(*info, m.getTopic());
              break;
            }
            case Kind::kImage:
            case Kind::kDepth: {
              if (!cameras.count(sensor)) {
                throw InputError("no usable camera_info for sensor '" + name + "' on " + rig.sensors[sensor].camera_info_topic);
              }
              const PinholeCamera camera = cameras[sensor];
              if (kind == Kind::kImage) {
                // A camera recorded through image_transport's compressed transport, or raw.
                const auto compressed = m.instantiate<sensor_msgs::CompressedImage>();
                const auto raw = compressed ? nullptr : m.instantiate<sensor_msgs::Image>();
                if (!compressed && !raw) throw InputError(m.getTopic() + ": not a sensor_msgs/Image or CompressedImage");
                ColorImage converted = compressed ? fromCompressedColorImage(*compressed, m.getTopic()) : fromColorImage(*raw, m.getTopic());
                const double stamp = (compressed ? compressed->header.stamp : raw->header.stamp).toSec();
                extraction = std::async(launch, [session, sensor = sensor, camera, lens = lenses[sensor], converted = std::move(converted)] {
                  return session->extractImage(sensor, converted, camera, lens);
                });
                pending.push_back({sensor, stamp, m.getTopic(), m.getTime(), std::move(extraction)});
                break;
              }
              const auto image = m.instantiate<sensor_msgs::Image>();
              if (!image) throw InputError(m.getTopic() + ": not a sensor_msgs/Image");
              extraction = std::async(launch, [session, sensor = sensor, camera, converted = fromDepthImage(*image, m.getTopic())] {
                return session->extractDepth(sensor, converted, camera);
              });
              pending.push_back({sensor, image->header.stamp.toSec(), m.getTopic(), m.getTime(), std::move(extraction)});
              break;
            }
            case Kind::kCloud: {
              const auto cloud = m.instantiate<sensor_msgs::PointCloud2>();
              if (!cloud) throw InputError(m.getTopic() + ": not a sensor_msgs/PointCloud2");
              std::vector<int> rings;
              std::vector<Eigen::Vector3d> points = fromPointCloud2(*cloud, m.getTopic(), &rings);
              session->prepareCloud(sensor, points, rings);
              if (!session->hasSpacing(sensor)) session->extractCloud(sensor, points);  // throws: says why
              extraction = std::async(launch, [session, sensor = sensor, points = std::move(points)] {
                return session->extractCloud(sensor, points);
              });
              pending.push_back({sensor, cloud->header.stamp.toSec(), m.getTopic(), m.getTime(), std::move(extraction)});
              break;
            }
            case Kind::kScan: {
              const auto scan = m.instantiate<sensor_msgs::LaserScan>();
              if (!scan) throw InputError(m.getTopic() + ": not a sensor_msgs/LaserScan");
              extraction = std::async(launch, [session, sensor = sensor, points = fromLaserScan(*scan, m.getTopic())] {
                return session->extractScan(sensor, points);
              });
              pending.push_back({sensor, scan->header.stamp.toSec(), m.getTopic(), m.getTime(), std::move(extraction)});
              break;
            }
            case Kind::kJointState:
              break;  // taken above, not a sensor's
          }
        } catch (const InputError& e) {
          drop(m.getTopic(), m.getTime(), e.what());
        }
        while (pending.size() > ahead) takeOldest();
      }
    }
    while (!pending.empty()) takeOldest();
  } catch (const rosbag::BagException& e) {
    throw InputError(bag_path + ": read failed (" + e.what() + ")");
  }
  return summary;
}

std::vector<CameraImage> readCameraImagesNear(const std::string& bag_path, const RigDescription& rig,
                                             const std::vector<CameraImageRequest>& requests) {
  rosbag::Bag bag;
  openBag(&bag, bag_path, rosbag::bagmode::Read);
  std::vector<CameraImage> images(requests.size());
  std::vector<std::unique_ptr<rosbag::MessageInstance>> nearest(requests.size());  // read once chosen: a JPEG decodes slowly
  try {
    std::map<std::string, std::vector<std::size_t>> requests_on;  // image topic -> requests
    std::map<int, CameraImage> info_of;  // per camera: its model and lens, found: its camera_info is usable
    for (std::size_t r = 0; r < requests.size(); ++r) {
      const int sensor = requests[r].sensor;
      const RigSensorDescription& d = rig.sensors.at(sensor);
      if (d.spec.type != SensorType::kCamera) throw InputError("sensor '" + d.spec.name + "' is not a camera");
      if (!info_of.count(sensor)) {
        CameraImage& info = info_of[sensor];
        info.found = firstUsableCameraInfo(bag, d.camera_info_topic, &info.camera, &info.lens);
      }
      images[r] = info_of[sensor];
      requests_on[d.image_topic].push_back(r);
    }
    std::vector<std::string> topics;
    for (const auto& entry : requests_on) topics.push_back(entry.first);
    rosbag::View view(bag, rosbag::TopicQuery(topics));
    for (const rosbag::MessageInstance& m : view) {
      // Raw, or through image_transport's compressed transport (the header alike).
      const auto compressed = m.instantiate<sensor_msgs::CompressedImage>();
      const auto raw = compressed ? nullptr : m.instantiate<sensor_msgs::Image>();
      if (!compressed && !raw) continue;
      const double stamp = (compressed ? compressed->header.stamp : raw->header.stamp).toSec();
      for (std::size_t r : requests_on.at(m.getTopic())) {
        if (!nearest[r] || std::abs(stamp - requests[r].stamp) < std::abs(images[r].stamp - requests[r].stamp)) {
          nearest[r] = std::make_unique<rosbag::MessageInstance>(m);
          images[r].stamp = stamp;
        }
      }
    }
    for (std::size_t r = 0; r < requests.size(); ++r) {
      images[r].found = images[r].found && nearest[r];
      if (!images[r].found) continue;
      const std::string& topic = rig.sensors[requests[r].sensor].image_topic;
      if (const auto compressed = nearest[r]->instantiate<sensor_msgs::CompressedImage>()) {
        images[r].image = fromCompressedColorImage(*compressed, topic);
      } else {
        images[r].image = fromColorImage(*nearest[r]->instantiate<sensor_msgs::Image>(), topic);
      }
    }
  } catch (const rosbag::BagException& e) {
    throw InputError(bag_path + ": read failed (" + e.what() + ")");
  }
  return images;
}

}  // namespace vocal
