// bag_odometry BAG --output TRAJ.txt [options]: the odometry straight from a bag (no master, no
// playback), as fast as the estimator runs: colour and depth paired by stamp (the TUM benchmark's
// rule, as tum_odometry pairs a folder), the latest camera_info for intrinsics; writes the camera trajectory in TUM format,
// prints frames per second and, with ground truth, ATE / RPE.

#include <chrono>
#include <cmath>
#include <cstdio>
#include <algorithm>
#include <iomanip>
#include <map>
#include <memory>
#include <optional>
#include <sstream>
#include <string>

#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/CameraInfo.h>
#include <sensor_msgs/Image.h>
#include <sensor_msgs/Imu.h>
#include <tf2/buffer_core.h>
#include <tf2/exceptions.h>
#include <tf2_eigen/tf2_eigen.h>
#include <tf2_msgs/TFMessage.h>

#include "vocal/core/errors.h"
#include "vocal/core/imu_samples.h"
#include "vocal/core/stamp_association.h"
#include "vocal/core/trajectory_evaluation.h"
#include "vocal/core/tum_trajectory.h"
#include "vocal/nodelets/message_conversions.h"
#include "vocal/odometry/gyro_rotation_prior.h"
#include "vocal/odometry/icp_dvo_odometry.h"
#include "vocal/odometry/odometry_config_yaml.h"
#include "vocal/tools/bag_file.h"
#include "vocal/tools/command_line.h"
#include "vocal/tools/trajectory_report.h"

namespace {
const char kUsage[] =
    "usage: bag_odometry BAG --output TRAJ.txt [options]\n"
    "  --rgb-topic T          colour images (default /camera/rgb/image_rect_color)\n"
    "  --depth-topic T        depth registered to colour, 16UC1 mm or 32FC1 m\n"
    "                         (default /camera/depth_registered/image_raw)\n"
    "  --camera-info-topic T  the colour camera's camera_info (default /camera/rgb/camera_info)\n"
    "                         (a TUM benchmark bag: --rgb-topic /camera/rgb/image_color\n"
    "                          --depth-topic /camera/depth/image)\n"
    "  --max-difference S     colour and depth stamps paired within this (default 0.02 s)\n"
    "  --config FILE.yaml     odometry settings (keys: see config/odometry.yaml)\n"
    "  --backend auto|cpu|reference|opencl  overrides the config's backend\n"
    "  --threads N            CPU threads (overrides the config's; 0 = OMP_NUM_THREADS, else the cores)\n"
    "  --imu-topic T          an IMU's sensor_msgs/Imu with angular velocity (a RealSense's /camera/imu): its\n"
    "                         gyro's rotation between frames as a prior; its pose in the camera from the bag's\n"
    "                         /tf_static (message frame -> colour image frame) unless --imu-extrinsics\n"
    "  --imu-extrinsics FILE  imu_extrinsics.yaml (README) instead of /tf_static\n"
    "  --imu-time-offset S    IMU stamp = camera stamp + S (default 0, or the extrinsics file's)\n"
    "  --groundtruth FILE     TUM trajectory to evaluate against (ATE / RPE)\n"
    "  --delta S              RPE interval (default 1 s)\n"
    "  --quiet                no progress bar\n";

using ImageMsg = sensor_msgs::Image;
using CameraInfoMsg = sensor_msgs::CameraInfo;

// Every required topic is in the bag with the right type, or an error names what is there.
void checkTopics(const rosbag::Bag& bag, const std::string& path, const std::map<std::string, std::string>& wanted) {
  std::map<std::string, std::string> present;
  rosbag::View all(bag);
  for (const rosbag::ConnectionInfo* c : all.getConnections()) present[c->topic] = c->datatype;
  for (const auto& [topic, type] : wanted) {
    const auto found = present.find(topic);
    if (found != present.end() && found->second == type) continue;
    std::ostringstream message;
    message << path << ": ";
    if (found == present.end()) {
      message << "no messages on " << topic << " (" << type << ")";
    } else {
      message << topic << " carries " << found->second << ", expected " << type;
    }
    message << "; the bag has:";
    for (const auto& [t, ty] : present) message << " " << t << " [" << ty << "]";
    throw vocal::InputError(message.str());
  }
}

// The first message's frame_id on `topic` (sensor_msgs/Image).
std::string firstImageFrame(const rosbag::Bag& bag, const std::string& topic) {
  rosbag::View view(bag, rosbag::TopicQuery(topic));
  for (const rosbag::MessageInstance& m : view) return m.instantiate<ImageMsg>()->header.frame_id;
  return "";
}

// The IMU on --imu-topic, read ahead: the gyro (messages with angular velocity, REP-145:
// angular_velocity_covariance[0] not -1) as a rotation prior, every message's acceleration (in the camera
// frame, on the camera's clock) for gravity; a NaN or a stamp not after the last one's dropped and
// counted. Its pose in the camera from --imu-extrinsics or the bag's /tf_static. A line says what is used.
struct BagImu {
  std::unique_ptr<vocal::GyroRotationPrior> gyro;  // null for an accelerometer alone
  std::vector<vocal::AccelerometerSample> accelerometer;
  std::string line;
  int dropped = 0;
};

BagImu openBagImu(const rosbag::Bag& bag, const std::string& path, const vocal::CommandLine& args, const std::string& camera_frame) {
  const std::string topic = args.text("imu-topic", "");
  BagImu imu;
  std::vector<vocal::ImuSample> rates;
  std::vector<vocal::AccelerometerSample> forces;
  std::string imu_frame, first_drop;
  double last_stamp = -1.0;
  rosbag::View view(bag, rosbag::TopicQuery(topic));
  for (const rosbag::MessageInstance& m : view) {
    const sensor_msgs::Imu::ConstPtr msg = m.instantiate<sensor_msgs::Imu>();
    std::ostringstream what;
    what << topic << " at " << std::fixed << std::setprecision(6) << msg->header.stamp.toSec();
    try {
      if (!(msg->header.stamp.toSec() > last_stamp)) throw vocal::InputError(what.str() + ": not after the previous message");
      forces.push_back(vocal::fromImuAcceleration(*msg, what.str()));
      if (msg->angular_velocity_covariance[0] != -1.0) rates.push_back(vocal::fromImuMessage(*msg, what.str()));
      last_stamp = msg->header.stamp.toSec();
      if (imu_frame.empty()) imu_frame = msg->header.frame_id;
    } catch (const vocal::InputError& e) {
      if (imu.dropped++ == 0) first_drop = e.what();
    }
  }
  if (forces.size() < 2) {
    std::ostringstream message;
    message << path << ": " << topic << " has " << forces.size() << " usable messages";
    if (imu.dropped > 0) message << "; " << imu.dropped << " dropped, the first: " << first_drop;
    throw vocal::InputError(message.str());
  }
  if (imu.dropped > 0) std::fprintf(stderr, "imu: %d messages dropped, the first: %s\n", imu.dropped, first_drop.c_str());
  vocal::ImuExtrinsics extrinsics;
  std::string source;
  if (args.has("imu-extrinsics")) {
    source = args.text("imu-extrinsics", "");
    extrinsics = vocal::readImuExtrinsics(source);
  } else {
    tf2::BufferCore transforms;
    rosbag::View statics(bag, rosbag::TopicQuery("/tf_static"));
    for (const rosbag::MessageInstance& m : statics) {
      if (const tf2_msgs::TFMessage::ConstPtr msg = m.instantiate<tf2_msgs::TFMessage>()) {
        for (const geometry_msgs::TransformStamped& t : msg->transforms) transforms.setTransform(t, "bag", true);
      }
    }
    try {
      extrinsics.camera_in_imu = tf2::transformToEigen(transforms.lookupTransform(imu_frame, camera_frame, ros::Time(0)));
    } catch (const tf2::TransformException& e) {
      throw vocal::InputError(path + ": no transform from the IMU's frame '" + imu_frame + "' (" + topic + ") to the camera's '" +
                              camera_frame + "' on /tf_static, needed to turn its readings into the camera's (or give " +
                              "--imu-extrinsics FILE): " + e.what());
    }
    extrinsics.imu_frame = imu_frame;
    extrinsics.camera_frame = camera_frame;
    source = "the bag's /tf_static (" + imu_frame + " <- " + camera_frame + ")";
  }
  extrinsics.time_offset = args.number("imu-time-offset", extrinsics.time_offset);
  const Eigen::Matrix3d camera_from_imu = extrinsics.camera_in_imu.linear().transpose();
  for (vocal::AccelerometerSample s : forces) {
    s.stamp -= extrinsics.time_offset;
    s.specific_force = camera_from_imu * s.specific_force;
    imu.accelerometer.push_back(s);
  }
  char text[1024];
  if (rates.size() >= 2) {
    imu.gyro = std::make_unique<vocal::GyroRotationPrior>(extrinsics);
    imu.gyro->add(rates);
    std::snprintf(text, sizeof(text), "imu: %zu samples on %s at %.0f Hz, camera in the IMU frame from %s (time offset %.4f s): the gyro's rotation as a prior, its bias estimated online",
                  rates.size(), topic.c_str(), vocal::imuRate(rates), source.c_str(), extrinsics.time_offset);
  } else {
    std::snprintf(text, sizeof(text), "imu: %zu accelerometer samples on %s (no angular velocity: REP-145's angular_velocity_covariance[0] = -1), camera in its frame from %s (time offset %.4f s): no gyro",
                  forces.size(), topic.c_str(), source.c_str(), extrinsics.time_offset);
  }
  imu.line = text;
  return imu;
}

void progress(std::size_t done, std::size_t total) {
  const int width = 30;
  const int filled = total ? static_cast<int>(width * done / total) : width;
  std::fprintf(stderr, "\r[%s%s] %zu/%zu messages", std::string(filled, '#').c_str(),
               std::string(width - filled, ' ').c_str(), done, total);
}

int run(const vocal::CommandLine& args) {
  if (!args.has("output")) throw vocal::InputError("--output TRAJ.txt is required");
  vocal::OdometryConfig config;
  if (args.has("config")) config = vocal::readOdometryConfigYaml(args.text("config", ""));
  if (args.has("backend")) config.backend = vocal::parseOdometryBackend(args.text("backend", ""));
  config.threads = args.integer("threads", config.threads);
  const std::string rgb_topic = args.text("rgb-topic", "/camera/rgb/image_rect_color");
  const std::string depth_topic = args.text("depth-topic", "/camera/depth_registered/image_raw");
  const std::string info_topic = args.text("camera-info-topic", "/camera/rgb/camera_info");
  const double max_difference = args.number("max-difference", 0.02);
  const bool quiet = args.has("quiet");
  vocal::Trajectory groundtruth;
  if (args.has("groundtruth")) groundtruth = vocal::readTumTrajectory(args.text("groundtruth", ""));

  const std::string path = args.positional()[0];
  rosbag::Bag bag;
  vocal::openBag(&bag, path, rosbag::bagmode::Read);
  std::map<std::string, std::string> wanted{
      {rgb_topic, "sensor_msgs/Image"}, {depth_topic, "sensor_msgs/Image"}, {info_topic, "sensor_msgs/CameraInfo"}};
  if (args.has("imu-topic")) wanted[args.text("imu-topic", "")] = "sensor_msgs/Imu";
  checkTopics(bag, path, wanted);
  BagImu bag_imu;
  if (args.has("imu-topic")) bag_imu = openBagImu(bag, path, args, firstImageFrame(bag, rgb_topic));
  vocal::GyroRotationPrior* const imu = bag_imu.gyro.get();
  std::fprintf(stderr, "%s\n", args.has("imu-topic") ? bag_imu.line.c_str() : "no IMU (no --imu-topic)");
  const bool gravity = !bag_imu.accelerometer.empty() && config.gravity_time_constant > 0.0;
  if (!bag_imu.accelerometer.empty()) {
    std::fprintf(stderr, gravity ? "its accelerometer holds roll and pitch to gravity (time constant %.1f s)\n"
                                 : "its accelerometer is not used (gravity_time_constant %.0f)\n", config.gravity_time_constant);
  }

  std::unique_ptr<vocal::IcpDvoOdometry> odometry;
  bool said_lens_problem = false;  // a lens the odometry cannot undo is said once
  vocal::Trajectory trajectory;
  double tracking_seconds = 0.0;
  int failures = 0, relocalisations = 0, dropped = 0, imu_priors = 0, imu_gaps = 0, degraded = 0;
  std::string imu_gap;
  std::string first_drop;
  CameraInfoMsg::ConstPtr info;

  auto track = [&](const ImageMsg& rgb, const ImageMsg& depth) {
    if (!info) throw vocal::InputError(path + ": " + rgb_topic + " at " + std::to_string(rgb.header.stamp.toSec()) +
                                       " comes before any message on " + info_topic);
    const vocal::PinholeCamera camera = vocal::fromCameraInfo(*info, info_topic);
    std::string lens_problem;
    const vocal::LensDistortion lens = vocal::odometryLensFromCameraInfo(*info, info_topic, &lens_problem);
    if (!lens_problem.empty() && !said_lens_problem) {
      std::fprintf(stderr, "%s\n", lens_problem.c_str());
      said_lens_problem = true;
    }
    if (!odometry || !(odometry->camera() == camera) || !(odometry->lens() == lens)) {
      std::string notice;
      auto backend = vocal::makeOdometryBackend(camera, config, &notice);
      if (!notice.empty() && !odometry) std::fprintf(stderr, "%s\n", notice.c_str());
      odometry = std::make_unique<vocal::IcpDvoOdometry>(camera, config, std::move(backend), lens);
      std::fprintf(stderr, "%dx%d camera: %s\n", camera.width, camera.height, odometry->cameraModelText().c_str());
      if (!trajectory.empty()) odometry->reset(trajectory.back().pose);  // new intrinsics: continue the path
    }
    const vocal::RgbdFrame frame = vocal::toRgbdFrame(rgb, depth, rgb_topic, depth_topic);
    const auto start = std::chrono::steady_clock::now();
    std::optional<vocal::RotationPrior> gyro;
    if (imu && !trajectory.empty()) {
      gyro = imu->between(trajectory.back().stamp, frame.stamp, &imu_gap);
      ++(gyro ? imu_priors : imu_gaps);
    }
    const vocal::OdometryResult result = odometry->track(frame, gyro ? &*gyro : nullptr, gravity ? &bag_imu.accelerometer : nullptr);
    if (imu) {
      if (result.state == vocal::TrackingState::kTracking && result.quality.trusted) {
        imu->observe(result.keyframe_stamp, frame.stamp, result.vision_rotation);
      } else {
        imu->breakWindow();
      }
    }
    degraded += result.state == vocal::TrackingState::kDegraded;
    tracking_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    trajectory.push_back({rgb.header.stamp.toSec(), result.pose});
    failures += !result.quality.trusted;
    relocalisations += result.state == vocal::TrackingState::kRelocalised;
    const std::string event = vocal::trackingEvent(result);
    if (!quiet && !event.empty()) std::fprintf(stderr, "\nframe at %.6f: %s\n", rgb.header.stamp.toSec(), event.c_str());
  };
  // Pass 1: the stamps of both image streams, paired by the TUM benchmark's rule (as tum_odometry
  // pairs a TUM folder's lists). Pass 2: each pair tracked as soon as both of its messages are read,
  // so only the messages between a pair's halves are held.
  rosbag::View view(bag, rosbag::TopicQuery({rgb_topic, depth_topic, info_topic}));
  const std::size_t total = 2 * view.size();
  std::size_t done = 0;
  auto step = [&] {
    if (!quiet && (++done % 20 == 0 || done == total)) progress(done, total);
  };
  // An image whose stamp is not after the last one kept on its topic (out of order, or a bag recorded
  // over a looped playback) is dropped and counted: the pairing needs increasing stamps.
  std::vector<double> rgb_stamps, depth_stamps;
  std::vector<long> rgb_kept, depth_kept;  // per message on the topic: its index among the kept, -1 if dropped
  int out_of_order = 0;
  for (const rosbag::MessageInstance& m : view) {
    const bool is_rgb = m.getTopic() == rgb_topic;
    if (is_rgb || m.getTopic() == depth_topic) {
      std::vector<double>& stamps = is_rgb ? rgb_stamps : depth_stamps;
      std::vector<long>& kept = is_rgb ? rgb_kept : depth_kept;
      const double stamp = m.instantiate<ImageMsg>()->header.stamp.toSec();
      if (stamps.empty() || stamp > stamps.back()) {
        kept.push_back(static_cast<long>(stamps.size()));
        stamps.push_back(stamp);
      } else {
        kept.push_back(-1);
        if (out_of_order++ == 0 && !quiet) {
          std::fprintf(stderr, "\n%s: %s at %.6f is not after the previous image's %.6f: dropped (and any others, counted)\n",
                       path.c_str(), m.getTopic().c_str(), stamp, stamps.back());
        }
      }
    }
    step();
  }
  const std::vector<vocal::StampMatch> pairs = vocal::associateStamps(rgb_stamps, depth_stamps, max_difference);
  const int unpaired = static_cast<int>(rgb_stamps.size() - pairs.size());
  std::vector<bool> rgb_needed(rgb_stamps.size()), depth_needed(depth_stamps.size());
  for (const vocal::StampMatch& pair : pairs) rgb_needed[pair.first] = depth_needed[pair.second] = true;
  std::map<std::size_t, ImageMsg::ConstPtr> rgb_held, depth_held;
  std::size_t next_pair = 0, rgb_index = 0, depth_index = 0;
  for (const rosbag::MessageInstance& m : view) {
    if (m.getTopic() == info_topic) {
      info = m.instantiate<CameraInfoMsg>();
    } else if (m.getTopic() == rgb_topic) {
      const long i = rgb_kept[rgb_index++];
      if (i >= 0 && rgb_needed[i]) rgb_held[i] = m.instantiate<ImageMsg>();
    } else {
      const long i = depth_kept[depth_index++];
      if (i >= 0 && depth_needed[i]) depth_held[i] = m.instantiate<ImageMsg>();
    }
    while (next_pair < pairs.size() && rgb_held.count(pairs[next_pair].first) && depth_held.count(pairs[next_pair].second)) {
      const vocal::StampMatch& pair = pairs[next_pair++];
      // A bad frame (encoding, size, camera_info) is named, counted and passed over; the rest go on.
      try {
        track(*rgb_held[pair.first], *depth_held[pair.second]);
      } catch (const vocal::InputError& e) {
        if (dropped++ == 0) first_drop = e.what();
        if (!quiet && dropped <= 5) std::fprintf(stderr, "\nframe dropped: %s%s\n", e.what(), dropped == 5 ? " (further drops only counted)" : "");
      }
      rgb_held.erase(rgb_held.begin(), rgb_held.upper_bound(pair.first));
      depth_held.erase(depth_held.begin(), depth_held.upper_bound(pair.second));
    }
    step();
  }
  if (!quiet) std::fprintf(stderr, "\n");
  if (trajectory.empty() && dropped > 0) throw vocal::InputError("every frame was dropped; the first: " + first_drop);
  if (trajectory.empty()) {
    throw vocal::InputError(path + ": no colour image on " + rgb_topic + " has a depth image on " + depth_topic +
                            " within " + std::to_string(max_difference) + " s");
  }
  vocal::writeTumTrajectory(args.text("output", ""), trajectory);
  std::printf("frames: %zu\nunpaired_colour_images: %d\nimages_out_of_order: %d\nframes_dropped: %d\ntracking_failures: %d\n"
              "relocalisations: %d\nframes_per_second: %.2f\n",
              trajectory.size(), unpaired, out_of_order, dropped, failures, relocalisations,
              trajectory.size() / std::max(tracking_seconds, 1e-9));
  if (args.has("imu-topic")) std::printf("imu_messages_dropped: %d\n", bag_imu.dropped);
  if (imu) {
    const Eigen::Vector3d bias = imu->bias() * 180.0 / M_PI;
    std::printf("imu_priors: %d\nimu_gaps: %d\ndegraded_frames: %d\ngyro_bias_deg_per_s: %.3f %.3f %.3f (+- %.3f, %d updates)\n",
                imu_priors, imu_gaps, degraded, bias.x(), bias.y(), bias.z(), imu->biasSigma().maxCoeff() * 180.0 / M_PI,
                imu->biasUpdates());
    if (imu_gaps > 0) std::fprintf(stderr, "imu: %d frames tracked without the gyro; the last because %s\n", imu_gaps, imu_gap.c_str());
  }
  if (!groundtruth.empty()) {
    vocal::printTrajectoryMetrics(stdout, vocal::computeAte(groundtruth, trajectory),
                                  vocal::computeRpe(groundtruth, trajectory, args.number("delta", 1.0)));
  }
  return 0;
}
}  // namespace

int main(int argc, char** argv) {
  return vocal::runTool("bag_odometry", kUsage, run, argc, argv,
                        {"output", "rgb-topic", "depth-topic", "camera-info-topic", "max-difference", "config", "backend",
                         "threads", "groundtruth", "delta", "imu-topic", "imu-extrinsics", "imu-time-offset"},
                        {"quiet"}, 1);
}
