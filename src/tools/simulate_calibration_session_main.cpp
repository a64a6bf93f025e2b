// simulate_calibration_session OUT_DIR [options]: a recorded calibration session of a simulated rig
// as a rosbag (depth images, lidar clouds, laser scans, camera images of a checkerboard moved through a
// room and held still at each pose), with the rig description calibrate_rig needs and the ground truth.

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iomanip>
#include <optional>
#include <sstream>
#include <string>
#include <utility>

#include "vocal/core/errors.h"
#include "vocal/core/folders.h"
#include "vocal/core/se3.h"
#include "vocal/simulation/rig_simulator.h"
#include "vocal/simulation/simulated_arm.h"
#include "vocal/tools/calibration_bag.h"
#include "vocal/tools/camera_imu_bag.h"
#include "vocal/tools/hand_eye_bag.h"
#include "vocal/tools/command_line.h"

namespace {
const char kUsage[] =
    "usage: simulate_calibration_session OUT_DIR [options]\n"
    "  --rgbd N --lidar N --laser N --camera N   sensors (default 1 RGB-D, 1 lidar, 1 2D laser, 1 camera;\n"
    "                                            the first RGB-D sensor is the reference)\n"
    "  --poses N           still target poses (default 12)\n"
    "  --turn RAD          how far the target turns left / right (default: as far as it tilts, 0.6 rad);\n"
    "                      e.g. 0.03: tilted mainly up and down (calibrate_rig's board edges)\n"
    "  --noise M           range noise, metres (default 0.001)\n"
    "  --room ROOM         plain (default: floor and one wall) or furnished (walls all round, ceiling, a\n"
    "                      cabinet whose front is the board's size, a table, a shelf, a sofa)\n"
    "  --person            someone holds the board by its sides (furnished rooms)\n"
    "  --lidar-noise M     the lidar's range noise, metres (default --noise; a VLP-16's is ~0.02)\n"
    "  --laser-noise M     the 2D laser's range noise, metres (default --noise; a Hokuyo UTM-30LX's is ~0.01-0.03)\n"
    "  --laser-beam M,RAD  the 2D laser's beam across: metres at its exit and its divergence (default 0,0: a\n"
    "                      ray; a SICK LMS1xx's is 0.008,0.015): a beam partly on the board returns from it\n"
    "  --ring-bias M       each lidar ring's range bias, drawn from +-M metres (default 0)\n"
    "  --range-offset M    a range offset every lidar ring shares, metres (default 0)\n"
    "  --vertical-offsets  each VLP-16 laser at its own height (the manual's +-11 mm): points' elevations drift\n"
    "                      with range; the clouds' ring field says which laser\n"
    "  --dark-range-offset M   lidar returns on the board's dark squares read M metres long (intensity-\n"
    "                      dependent range; default 0)\n"
    "  --lidar-model M     vlp16 (default: 16 rings), ouster64 (64 rings over +-16.6 degrees), livox (a\n"
    "                      non-repeating rosette over a 70-degree cone ahead, no rings) or scanner (77\n"
    "                      elevation bands over +-19 degrees, 120 degrees ahead, clouds without a ring\n"
    "                      field); livox and scanner turned to face the target\n"
    "  --mixed-pixels      returns between two surfaces where a beam straddles an edge\n"
    "  --rate HZ           messages per second of every sensor (default 10), unsynchronised\n"
    "  --camera-rate HZ --rgbd-rate HZ --lidar-rate HZ --laser-rate HZ   one sensor type's own rate\n"
    "  --still S --moving S   seconds the target is held still at each pose (default 0.6) and carried\n"
    "                      to the next (default 0.4)\n"
    "  --lens MODEL[,MODEL...]   each camera's lens, in turn: none (default), plumb_bob (wide angle, k1\n"
    "                      -0.3), rational_polynomial (8 coefficients, as an Azure Kinect colour camera's) or\n"
    "                      equidistant (fisheye); images rendered through it, camera_info carries it\n"
    "  --board-width M --board-height M   the board (default 0.9 x 0.7)\n"
    "  --pattern-cols N --pattern-rows N --square M   its checkerboard's inner corners and squares\n"
    "                      (default 8 x 6, 0.06 m; the columns run along the width)\n"
    "  --faults F[,F...]   faults of one sensor each, for checking that calibrate_rig flags them:\n"
    "                      moves:SENSOR:RAD (on a pan-tilt head the rig does not describe, turned by up to RAD\n"
    "                      at each still pose), bumped:SENSOR:M (moved M metres and M rad half way through),\n"
    "                      time-offset:SENSOR:S (its stamps S seconds late), focal:SENSOR:SCALE (a camera's\n"
    "                      camera_info focal length times SCALE); ground_truth.yaml keeps the mount as built;\n"
    "                      an arm's session takes them too (its sensors, the arm's still poses)\n"
    "  --dark-absorbs      lidar beams on the board's dark squares return nothing\n"
    "  --stand             the board stands on two posts with feet, carried with it (no one holds it)\n"
    "  --crop-lidar M      each lidar cloud cropped to the returns within M metres of a still pose's board\n"
    "  --seed S            (default 1)\n"
    "  --pan-tilt          an RGB-D camera (head_camera) on a pan-tilt head, turned towards the board at each\n"
    "                      still pose, in front of the lidar (the reference) and the 2D laser fixed on the\n"
    "                      robot: the head's joints on /joint_states at 200 Hz, each off by a drawn zero\n"
    "                      offset (+-0.03 rad), 12-bit encoders, 1 mrad of backlash; rig.yaml lists the\n"
    "                      joints (offsets unknown), ground_truth.yaml their true offsets and the camera's\n"
    "                      mount on the tilt link\n"
    "  --pose-known        (with --pan-tilt) rig.yaml gives the camera's mount as known (pose_known: true)\n"
    "  --head-laser        (with --pan-tilt) the 2D laser on the head's tilt link too (head_laser, 5 cm under the\n"
    "                      camera, scanning across its line of sight), its mount unknown\n"
    "writes OUT_DIR/session.bag, OUT_DIR/rig.yaml (the reference's pose only) and\n"
    "OUT_DIR/ground_truth.yaml (every sensor's true pose, same format)\n"
    "\n"
    "A robot arm instead (hand-eye), the arm on /tf at 200 Hz (base -> flange) and /tf_static (flange -> tool):\n"
    "  --eye-in-hand       a camera on the arm's tool over a board fixed on the table\n"
    "  --eye-to-hand       a camera on a post watching the board in the arm's gripper\n"
    "  --poses N           still poses of the arm (default 12), each 1 s still, 2 s moving; the camera at 10 Hz\n"
    "  --arm-noise M       the arm's repeatability: each reported tool pose off by M metres and M radians\n"
    "                      (standard deviation per axis; default 0.0001)\n"
    "  --poor-pose K       the K-th still pose's tool reported 5 mm off (default: none)\n"
    "  --compressed        images as image_transport's compressed transport records them (JPEG, on\n"
    "                      /arm_camera/image_raw/compressed)\n"
    "  --beside            (eye-to-hand) a VLP-16-like lidar, an RGB-D camera and a 2D laser (270 degrees,\n"
    "                      1 cm noise) fixed beside the camera, in the same session; (eye-in-hand) a 2D laser\n"
    "                      on the tool beside the camera (tool_laser), its scan line across the board\n"
    "  --given-reference   (eye-to-hand) rig.yaml gives the fixed camera's true pose in the base frame (the\n"
    "                      reference, held by the calibration)\n"
    "  --laser-beam M,RAD  (--beside) the 2D laser's beam across, as for still poses above\n"
    "  --board-depths NEAR,FAR   (--eye-to-hand) the board NEAR to FAR metres from the camera (default 0.6,0.9);\n"
    "                      with --beside its centre at the 2D laser's height, so that the laser's scan crosses\n"
    "                      it at every pose: a session for the laser, at ranges that tell its height from its pitch\n"
    "  --pattern-cols N --pattern-rows N --square M --board-width M --board-height M   the board (default\n"
    "                      10 x 7 inner corners of 0.03 m on 0.36 x 0.27 m)\n"
    "  --arm               a 6-joint arm (1.1 m reach) reaches the poses: its readings on /joint_states at 200 Hz\n"
    "                      (each joint's zero off by up to --joint-offsets, default 0.005 rad; 16-bit encoders;\n"
    "                      --joint-noise R per reading at a pose, default 0.0002 rad), /tf from the readings as\n"
    "                      robot_state_publisher gives it; rig.yaml names the joints (offsets unknown)\n"
    "  --forearm           (--arm) a second camera on the arm's forearm_link, where the main camera was at one\n"
    "                      pose (10 cm behind the wrist camera, or 30 cm ahead of the post camera)\n"
    "  --head              (--arm) a pan-tilt head beside the arm, a metre from its base, with a camera\n"
    "                      (head_camera on head_tilt_link) turned towards the board at each still pose; its\n"
    "                      joints on /joint_states with the arm's, their zeros off like the arm's\n"
    "  --link-error M      (--arm) the true upper arm M metres longer than rig.yaml's model (elbow_joint's origin);\n"
    "                      (--pan-tilt) the tilt joint M metres higher than the model's (head_tilt_joint's origin)\n"
    "  --free-origins J[,J...]   (--arm, --pan-tilt) rig.yaml's free_joint_origins: those joints' origins solved too\n"
    "  --seed S\n"
    "writes OUT_DIR/session.bag, OUT_DIR/rig.yaml and OUT_DIR/ground_truth.yaml (the camera and the board\n"
    "in their parents, every still pose's tool)\n"
    "\n"
    "A camera and an IMU waved before a fixed board instead (a camera-IMU session, as Kalibr's users record one):\n"
    "  --waved-imu         a 640x480 camera (wide-angle lens) with a consumer MEMS IMU beside it, waved before a 6 x 7\n"
    "                      board of 5 cm squares, turning about and moving along all three axes; images on\n"
    "                      /camera/image_raw (mono8), camera_info, the IMU's sensor_msgs/Imu on /imu/data\n"
    "  --seconds S         how long (default 60)\n"
    "  --camera-rate HZ --imu-rate HZ   (default 20 and 200)\n"
    "  --time-offset S     the IMU's stamps S seconds ahead of the camera's (default 0.01)\n"
    "  --motion M          all (default), one-axis (turns about the optical axis only) or none (never turns)\n"
    "  --compressed        images as JPEG on /camera/image_raw/compressed\n"
    "  --pattern-cols N --pattern-rows N --square M --board-width M --board-height M   the board (default 7 x 6\n"
    "                      inner corners of 0.05 m on 0.5 x 0.45 m; a larger one is waved before from further away)\n"
    "  --camera-name NAME  the camera's name and topics (/NAME/image_raw, /NAME/camera_info; default camera):\n"
    "                      a still-pose session's camera0 to calibrate its IMU with calibrate_rig --imu-bag\n"
    "  --seed S\n"
    "writes OUT_DIR/session.bag, OUT_DIR/rig.yaml (the camera the reference, the IMU without a pose) and\n"
    "OUT_DIR/ground_truth.yaml (the camera in the IMU, the IMU in the rig, the time offset and the biases)\n";

// --free-origins J[,J...]: rig.yaml's free_joint_origins.
std::vector<std::string> freeOriginsOption(const vocal::CommandLine& args) {
  std::vector<std::string> names;
  std::stringstream list(args.text("free-origins", ""));
  for (std::string name; std::getline(list, name, ',');) names.push_back(name);
  return names;
}

// --link-error and --free-origins change a robot's joints: with --arm or --pan-tilt (`with`, the session's).
void checkJointModelOptions(const vocal::CommandLine& args, const char* with) {
  for (const char* option : {"link-error", "free-origins"}) {
    if (args.has(option) && !args.has(with)) {
      throw vocal::InputError(std::string("option --") + option + ": with --arm or --pan-tilt (a link of the robot's joints)");
    }
  }
}

// --faults F[,F...], each of a sensor in `sensors` (parseSimulatedSensorFault).
std::vector<vocal::SimulatedSensorFault> faultsOption(const vocal::CommandLine& args, const std::vector<vocal::SimulatedSensor>& sensors) {
  std::vector<vocal::SimulatedSensorFault> faults;
  const std::string text = args.text("faults", "");
  for (std::size_t begin = 0; !text.empty() && begin <= text.size();) {
    const std::size_t end = std::min(text.find(',', begin), text.size());
    faults.push_back(vocal::parseSimulatedSensorFault(text.substr(begin, end - begin), sensors, "option --faults"));
    begin = end + 1;
  }
  return faults;
}

// "A,B" as two numbers; false where it is not that.
bool numberPair(const std::string& text, double* a, double* b) {
  char* end = nullptr;
  *a = std::strtod(text.c_str(), &end);
  if (end == text.c_str() || *end != ',') return false;
  const char* second = end + 1;
  *b = std::strtod(second, &end);
  return end != second && *end == '\0';
}

// --laser-beam M,RAD: the 2D laser's beam width at its exit and divergence (SimulatedRoomView).
void laserBeamOption(const vocal::CommandLine& args, double* aperture, double* divergence) {
  if (!args.has("laser-beam")) return;
  const std::string text = args.text("laser-beam", "");
  if (!numberPair(text, aperture, divergence)) throw vocal::InputError("option --laser-beam: '" + text + "' is not M,RAD (e.g. 0.008,0.015)");
  if (!(*aperture >= 0.0 && *aperture < 0.1) || !(*divergence >= 0.0 && *divergence < 0.1)) {
    throw vocal::InputError("option --laser-beam: '" + text + "' is not M,RAD with each from 0 to 0.1 (e.g. 0.008,0.015)");
  }
}

// A robot arm's hand-eye session (hand_eye_bag.h).
int simulateHandEye(const vocal::CommandLine& args, const std::string& dir) {
  if (args.has("eye-in-hand") && args.has("eye-to-hand")) throw vocal::InputError("options --eye-in-hand and --eye-to-hand: give one");
  // The still-pose session's sensors, room and target motion are not the arm's: refused rather than left
  // unused, so that a session is what its command line says.
  for (const char* still_only : {"rgbd", "lidar", "laser", "camera", "noise", "rate", "lens", "room", "lidar-noise", "laser-noise",
                                 "ring-bias", "turn", "range-offset", "lidar-model", "dark-range-offset", "camera-rate", "rgbd-rate",
                                 "lidar-rate", "laser-rate", "still", "moving", "crop-lidar", "person", "mixed-pixels", "vertical-offsets",
                                 "dark-absorbs", "stand", "pan-tilt", "pose-known", "head-laser"}) {
    if (args.has(still_only)) {
      throw vocal::InputError(std::string("option --") + still_only + ": not for an arm's session (--eye-in-hand, --eye-to-hand); " +
                              "its sensors are the camera and, with --beside, those fixed beside it");
    }
  }
  vocal::SimulatedArmOptions arm_options;
  arm_options.setup = args.has("eye-in-hand") ? vocal::HandEyeSetup::kEyeInHand : vocal::HandEyeSetup::kEyeToHand;
  arm_options.poses = args.integer("poses", arm_options.poses);
  if (arm_options.poses < 3) throw vocal::InputError("option --poses: at least 3 poses are needed");
  arm_options.tool_translation_noise = arm_options.tool_rotation_noise = args.number("arm-noise", arm_options.tool_translation_noise);
  if (!(arm_options.tool_translation_noise >= 0.0)) throw vocal::InputError("option --arm-noise: must be >= 0");
  arm_options.poor_pose = args.integer("poor-pose", 0) - 1;
  if (arm_options.poor_pose >= arm_options.poses || arm_options.poor_pose < -1) {
    throw vocal::InputError("option --poor-pose: a still pose from 1 to " + std::to_string(arm_options.poses));
  }
  arm_options.seed = static_cast<std::uint32_t>(args.integer("seed", 1));
  if (args.has("board-depths")) {
    if (arm_options.setup != vocal::HandEyeSetup::kEyeToHand) {
      throw vocal::InputError("option --board-depths: with --eye-to-hand (the board in the gripper before the camera)");
    }
    const std::string text = args.text("board-depths", "");
    if (!numberPair(text, &arm_options.near_depth, &arm_options.far_depth) || !(arm_options.near_depth >= 0.3) ||
        !(arm_options.far_depth >= arm_options.near_depth) || !(arm_options.far_depth <= 1.5)) {
      throw vocal::InputError("option --board-depths: '" + text + "' is not NEAR,FAR in metres with 0.3 <= NEAR <= FAR <= 1.5 (e.g. 0.45,1.2)");
    }
    arm_options.across_laser = args.has("beside");
  }
  vocal::TargetDescription target;
  target.pattern = {args.integer("pattern-rows", 7), args.integer("pattern-cols", 10), args.number("square", 0.03)};
  target.width = args.number("board-width", 0.36);
  target.height = args.number("board-height", 0.27);
  vocal::checkTargetDescription(target, "options --board-width, --board-height, --pattern-cols, --pattern-rows, --square");
  if (args.has("forearm") && !args.has("arm")) {
    throw vocal::InputError("option --forearm: with --arm (a camera on the forearm moves with the arm's first joints)");
  }
  if (args.has("head") && !args.has("arm")) throw vocal::InputError("option --head: with --arm (the head's joints are read with the arm's)");
  checkJointModelOptions(args, "arm");
  // --arm: a 6-joint arm reaches the poses; its readings on /joint_states, the rig names its joints.
  std::optional<vocal::SimulatedJointArm> joint_arm;
  if (args.has("arm")) {
    if (arm_options.poor_pose >= 0) throw vocal::InputError("option --poor-pose: not with --arm (its readings' noise is --joint-noise)");
    vocal::SimulatedJointArmOptions joint_options;
    joint_options.seed = arm_options.seed;
    joint_options.reading_noise = args.number("joint-noise", joint_options.reading_noise);
    joint_options.offset_range = args.number("joint-offsets", joint_options.offset_range);
    joint_options.head = args.has("head");
    joint_options.elbow_length_error = args.number("link-error", 0.0);
    if (!(joint_options.reading_noise >= 0.0)) throw vocal::InputError("option --joint-noise: must be >= 0");
    joint_arm = vocal::simulateJointArm(arm_options, joint_options);
  }
  const vocal::SimulatedArm arm = joint_arm ? joint_arm->arm : vocal::simulateArm(arm_options);
  vocal::RigDescription rig = joint_arm ? vocal::simulatedJointArmRig(arm_options.setup, target, *joint_arm, args.has("beside"), args.has("forearm"))
                                        : vocal::simulatedHandEyeRig(arm_options.setup, target, args.has("compressed"), args.has("beside"));
  if (args.has("given-reference")) {
    if (arm_options.setup != vocal::HandEyeSetup::kEyeToHand) {
      throw vocal::InputError("option --given-reference: with --eye-to-hand (the camera on the tool is no fixed reference)");
    }
    rig.sensors.front().pose = arm.camera;  // the fixed camera, in the base frame
  }
  rig.free_joint_origins = freeOriginsOption(args);
  vocal::writeRigDescription(dir + "/rig.yaml", rig);
  vocal::writeHandEyeGroundTruth(dir + "/ground_truth.yaml", arm, rig, arm_options.poor_pose, joint_arm ? &*joint_arm : nullptr);
  vocal::HandEyeBagOptions bag_options;
  bag_options.seed = arm_options.seed;
  std::vector<vocal::SimulatedSensor> named;
  for (const vocal::RigSensorDescription& d : rig.sensors) named.push_back({d.spec, Eigen::Isometry3d::Identity()});
  bag_options.faults = faultsOption(args, named);
  bag_options.compressed_images = args.has("compressed");
  if (args.has("laser-beam") && !args.has("beside")) throw vocal::InputError("option --laser-beam: with --beside (the arm's 2D laser)");
  laserBeamOption(args, &bag_options.laser_beam_aperture, &bag_options.laser_beam_divergence);
  bag_options.joint_arm = joint_arm ? &*joint_arm : nullptr;
  vocal::writeSimulatedHandEyeBag(arm, rig, bag_options, dir + "/session.bag");
  std::printf("wrote a %s session of %d arm poses to %s/session.bag; rig.yaml, ground_truth.yaml\n",
              vocal::handEyeSetupName(arm_options.setup).c_str(), arm_options.poses, dir.c_str());
  return 0;
}


// A camera and an IMU waved before a board (camera_imu_bag.h).
int simulateWavedImu(const vocal::CommandLine& args, const std::string& dir) {
  vocal::WavedCameraImuOptions options;
  options.duration = args.number("seconds", 60.0);
  options.camera_rate = args.number("camera-rate", options.camera_rate);
  options.imu_rate = args.number("imu-rate", options.imu_rate);
  options.time_offset = args.number("time-offset", 0.01);
  options.seed = static_cast<std::uint32_t>(args.integer("seed", 1));
  if (!(options.duration > 1.0)) throw vocal::InputError("option --seconds: must be over 1");
  if (!(options.camera_rate > 0.0 && options.imu_rate > 0.0)) throw vocal::InputError("options --camera-rate, --imu-rate: must be > 0");
  const std::string motion = args.text("motion", "all");
  if (motion == "one-axis") {
    options.motion = vocal::WavedMotion::kOneAxisTurns;
  } else if (motion == "none") {
    options.motion = vocal::WavedMotion::kNoTurns;
  } else if (motion != "all") {
    throw vocal::InputError("option --motion: '" + motion + "' is unknown: expected all, one-axis or none");
  }
  if (args.has("pattern-cols") || args.has("pattern-rows") || args.has("square")) {
    options.pattern = {args.integer("pattern-rows", options.pattern.rows), args.integer("pattern-cols", options.pattern.cols),
                       args.number("square", options.pattern.square_size)};
    // As far from a larger board as from the default one, so it stays in view as much.
    const double width = (options.pattern.cols + 1) * options.pattern.square_size, height = (options.pattern.rows + 1) * options.pattern.square_size;
    options.distance *= std::max(width / 0.4, height / 0.35);
  }
  const vocal::WavedCameraImuSession session = vocal::simulateWavedCameraImu(options);
  // The camera on the rig's body, looking ahead (REP-103 body to optical), a little up and to the left.
  Eigen::Isometry3d camera_in_rig = Eigen::Isometry3d::Identity();
  camera_in_rig.linear() = vocal::bodyFromOpticalRotation();
  camera_in_rig.translation() = Eigen::Vector3d(0.05, 0.02, 0.1);
  vocal::RigDescription rig = vocal::simulatedCameraImuRig(options, camera_in_rig, args.has("compressed"), args.text("camera-name", "camera"));
  rig.target.width = args.number("board-width", rig.target.width);
  rig.target.height = args.number("board-height", rig.target.height);
  vocal::checkTargetDescription(rig.target, "options --board-width, --board-height, --pattern-cols, --pattern-rows, --square");
  vocal::writeRigDescription(dir + "/rig.yaml", rig);
  {
    std::ofstream truth(dir + "/ground_truth.yaml");
    const auto pose = [&](const Eigen::Isometry3d& p) {
      const Eigen::Quaterniond q(p.rotation());
      std::ostringstream out;
      out << std::setprecision(10) << "[" << p.translation().x() << ", " << p.translation().y() << ", " << p.translation().z() << ", " << q.x()
          << ", " << q.y() << ", " << q.z() << ", " << q.w() << "]";
      return out.str();
    };
    const auto vector = [](const Eigen::Vector3d& v) {
      std::ostringstream out;
      out << std::setprecision(10) << "[" << v.x() << ", " << v.y() << ", " << v.z() << "]";
      return out.str();
    };
    truth << std::setprecision(10) << "# the truth of a simulated waved camera-IMU session\nreference_frame: base_link\n"
          << "camera_in_imu: " << pose(session.camera_in_imu) << "  # x y z qx qy qz qw: x_imu = T x_camera\n"
          << "imu_in_rig: " << pose(camera_in_rig * session.camera_in_imu.inverse()) << "\n"
          << "time_offset: " << session.time_offset << "  # s: IMU stamp = camera stamp + time_offset\n"
          << "gyro_bias: " << vector(session.gyro_bias) << "  # rad/s, the session's mean\n"
          << "accelerometer_bias: " << vector(session.accel_bias) << "  # m/s^2\n";
    if (!truth.flush()) throw vocal::InputError(dir + "/ground_truth.yaml: cannot write");
  }
  vocal::writeSimulatedWavedBag(session, options, rig, dir + "/session.bag");
  std::printf("wrote a waved camera-IMU session of %.0f s (%d frames, the board in %zu; %zu IMU samples) to %s/session.bag; rig.yaml, "
              "ground_truth.yaml\n",
              options.duration, session.frames, session.views.size(), session.imu.size(), dir.c_str());
  return 0;
}

int run(const vocal::CommandLine& args) {
  const std::string dir = args.positional()[0];
  vocal::makeFolders(dir);
  if (args.has("waved-imu")) return simulateWavedImu(args, dir);
  if (args.has("eye-in-hand") || args.has("eye-to-hand")) return simulateHandEye(args, dir);
  if (args.has("arm")) throw vocal::InputError("option --arm: with --eye-in-hand or --eye-to-hand");
  // An arm's options, refused rather than left unused.
  for (const char* arm_only : {"arm-noise", "poor-pose", "beside", "given-reference", "board-depths", "forearm", "head", "joint-noise", "joint-offsets"}) {
    if (args.has(arm_only)) throw vocal::InputError(std::string("option --") + arm_only + ": with --eye-in-hand or --eye-to-hand (a robot arm's session)");
  }
  const bool pan_tilt = args.has("pan-tilt");
  if (args.has("pose-known") && !pan_tilt) throw vocal::InputError("option --pose-known: with --pan-tilt");
  if (args.has("head-laser") && !pan_tilt) throw vocal::InputError("option --head-laser: with --pan-tilt");
  checkJointModelOptions(args, "pan-tilt");
  const int rgbd = args.integer("rgbd", 1);
  if (rgbd < 1) throw vocal::InputError("option --rgbd: the reference is an RGB-D sensor, at least 1 is needed");
  std::vector<vocal::SimulatedSensor> sensors =
      pan_tilt ? vocal::panTiltRig(args.has("head-laser")) : vocal::exampleRig(rgbd, args.integer("lidar", 1), args.integer("laser", 1), args.integer("camera", 1));
  const vocal::LidarModel lidar_model = vocal::parseLidarModel(args.text("lidar-model", "vlp16"), "option --lidar-model");
  // They see ahead, not all round.
  if (lidar_model == vocal::LidarModel::kLivox || lidar_model == vocal::LidarModel::kScanner) vocal::pointLidarsAhead(&sensors);
  vocal::TargetDescription target;  // the design's example board on a 0.9 x 0.7 m target, unless given
  target.width = args.number("board-width", target.width);
  target.height = args.number("board-height", target.height);
  target.pattern.cols = args.integer("pattern-cols", target.pattern.cols);
  target.pattern.rows = args.integer("pattern-rows", target.pattern.rows);
  target.pattern.square_size = args.number("square", target.pattern.square_size);
  vocal::checkTargetDescription(target, "options --board-width, --board-height, --pattern-cols, --pattern-rows, --square");
  vocal::SimulatedSessionOptions options;
  options.target_poses = args.integer("poses", 12);
  options.turn_range = args.number("turn", -1.0);
  options.range_noise = args.number("noise", 0.001);
  options.rate = args.number("rate", options.rate);
  if (!(options.rate > 0.0)) throw vocal::InputError("option --rate: messages per second must be > 0");
  for (const auto& [name, rate] : {std::pair<const char*, double*>{"camera-rate", &options.camera_rate}, {"rgbd-rate", &options.rgbd_rate},
                                   {"lidar-rate", &options.lidar_rate}, {"laser-rate", &options.laser_rate}}) {
    *rate = args.number(name, 0.0);
    if (args.has(name) && !(*rate > 0.0)) throw vocal::InputError(std::string("option --") + name + ": messages per second must be > 0");
  }
  options.still_seconds = args.number("still", options.still_seconds);
  options.moving_seconds = args.number("moving", options.moving_seconds);
  if (!(options.still_seconds > 0.0)) throw vocal::InputError("option --still: the seconds the target is held still must be > 0");
  if (!(options.moving_seconds > 0.0)) throw vocal::InputError("option --moving: the seconds the target is carried must be > 0");
  // Real magnitudes: a wide-angle lens and a fisheye as OpenCV calibrates them; one per camera.
  std::stringstream lenses(args.text("lens", "none"));
  for (std::string lens; std::getline(lenses, lens, ',');) {
    if (lens == "plumb_bob") {
      options.camera_lenses.push_back(vocal::LensDistortion::fromCameraInfo("plumb_bob", {-0.30, 0.09, 0.0012, -0.0008, -0.012}, "--lens"));
    } else if (lens == "rational_polynomial") {
      options.camera_lenses.push_back(vocal::LensDistortion::fromCameraInfo(
          "rational_polynomial", {0.52, -2.57, 0.0006, -0.0002, 1.46, 0.40, -2.41, 1.39}, "--lens"));
    } else if (lens == "equidistant") {
      options.camera_lenses.push_back(vocal::LensDistortion::fromCameraInfo("equidistant", {-0.013, 0.021, -0.011, 0.0021}, "--lens"));
    } else if (lens == "none") {
      options.camera_lenses.emplace_back();
    } else {
      throw vocal::InputError("option --lens: '" + lens + "' is unknown: expected none, plumb_bob, rational_polynomial or equidistant");
    }
  }
  const std::string room = args.text("room", "plain");
  if (room != "plain" && room != "furnished") throw vocal::InputError("option --room: '" + room + "' is unknown: expected plain or furnished");
  options.room = room == "furnished" ? vocal::RoomLayout::kFurnished : vocal::RoomLayout::kPlain;
  options.person_holds_target = args.has("person");
  if (options.person_holds_target && options.room != vocal::RoomLayout::kFurnished) {
    throw vocal::InputError("option --person: only in a furnished room (--room furnished)");
  }
  options.lidar_noise = args.number("lidar-noise", -1.0);
  options.laser_noise = args.number("laser-noise", -1.0);
  laserBeamOption(args, &options.laser_beam_aperture, &options.laser_beam_divergence);
  options.ring_bias = args.number("ring-bias", 0.0);
  options.lidar_range_offset = args.number("range-offset", 0.0);
  options.lidar_model = lidar_model;
  options.lidar_vertical_offsets = args.has("vertical-offsets");
  options.dark_range_offset = args.number("dark-range-offset", 0.0);
  options.mixed_pixels = args.has("mixed-pixels");
  options.seed = static_cast<std::uint32_t>(args.integer("seed", 1));
  options.dark_absorbs = args.has("dark-absorbs");
  options.board_on_stand = args.has("stand");
  options.lidar_crop = args.number("crop-lidar", 0.0);
  if (options.lidar_crop < 0.0) throw vocal::InputError("option --crop-lidar: metres must be >= 0");
  options.faults = faultsOption(args, sensors);
  if (options.target_poses < 3) throw vocal::InputError("option --poses: at least 3 poses are needed");
  vocal::RigDescription rig = vocal::describeSimulatedRig(sensors, target, false);
  vocal::RigDescription truth = vocal::describeSimulatedRig(sensors, target, true);
  if (pan_tilt) {
    vocal::putOnPanTiltHead(sensors, &options, &rig, &truth, args.has("pose-known"), Eigen::Vector3d(0.0, 0.0, args.number("link-error", 0.0)),
                            args.has("head-laser"));
  }
  rig.free_joint_origins = freeOriginsOption(args);
  vocal::writeRigDescription(dir + "/rig.yaml", rig);
  vocal::writeRigDescription(dir + "/ground_truth.yaml", truth);
  const vocal::SimulatedSessionSummary summary = vocal::writeSimulatedCalibrationBag(sensors, rig, options, dir + "/session.bag");
  std::printf("wrote %zu messages of %zu sensors at %d target poses to %s/session.bag; rig.yaml, ground_truth.yaml\n",
              summary.messages, sensors.size(), options.target_poses, dir.c_str());
  if (options.head) {
    std::printf("the head's joints on /joint_states at %.0f Hz; true zero offsets:", options.joint_state_rate);
    for (const vocal::JointDescription& joint : options.head->joints) std::printf(" %s %+.4f rad", joint.name.c_str(), joint.offset);
    std::printf("\n");
  }
  return 0;
}
}  // namespace

int main(int argc, char** argv) {
  return vocal::runTool("simulate_calibration_session", kUsage, run, argc, argv,
                        {"rgbd", "lidar", "laser", "camera", "poses", "noise", "seed", "rate", "lens", "room", "lidar-noise", "laser-noise", "ring-bias", "turn",
                         "range-offset", "lidar-model", "dark-range-offset",
                         "camera-rate", "rgbd-rate", "lidar-rate", "laser-rate", "still", "moving", "board-width",
                         "board-height", "pattern-cols", "pattern-rows", "square", "faults", "crop-lidar", "arm-noise", "poor-pose", "joint-noise", "joint-offsets", "link-error", "free-origins",
                         "seconds", "imu-rate", "time-offset", "motion", "camera-name", "laser-beam", "board-depths"},
                        {"person", "mixed-pixels", "vertical-offsets", "dark-absorbs", "stand", "eye-in-hand", "eye-to-hand", "compressed", "beside",
                         "pan-tilt", "pose-known", "head-laser", "arm", "given-reference", "forearm", "head", "waved-imu"}, 1);
}
