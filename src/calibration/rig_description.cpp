#include "vocal/calibration/rig_description.h"

#include <cmath>
#include <fstream>
#include <iomanip>
#include <set>

#include <yaml-cpp/yaml.h>

#include "vocal/calibration/urdf_joints.h"
#include "vocal/core/errors.h"
#include "vocal/core/yaml_file.h"
#include "vocal/core/se3.h"

namespace vocal {

std::vector<SensorSpec> RigDescription::specs() const {
  std::vector<SensorSpec> out;
  for (const RigSensorDescription& s : sensors) out.push_back(s.spec);
  return out;
}

bool RigDescription::isJointLink(const std::string& frame) const {
  if (frame.empty()) return false;
  for (const JointDescription& joint : joints)
    if (joint.child == frame) return true;
  return false;
}

bool RigDescription::behindJoints(int sensor) const { return isJointLink(sensors.at(sensor).parent); }

bool RigDescription::needsJointStates() const {
  if (joints.empty()) return false;
  const std::optional<HandEyeRig> arm = handEye();
  return arm ? arm->from_joints : !jointedMounts().chains.empty();
}

JointedMounts RigDescription::jointedMounts() const {
  JointedMounts mounts;
  mounts.joints = joints;
  if (handEye()) return mounts;  // an arm's rig: its tool's chain (HandEyeRig::chain), not per sensor
  bool any = false;
  for (std::size_t s = 0; s < sensors.size(); ++s) any = any || behindJoints(static_cast<int>(s));
  if (!any) return mounts;
  mounts.chains.resize(sensors.size());
  mounts.known_mounts.resize(sensors.size());
  for (std::size_t s = 0; s < sensors.size(); ++s) {
    if (!behindJoints(static_cast<int>(s))) continue;
    mounts.chains[s] = jointChain(joints, reference_frame, sensors[s].parent, "sensor '" + sensors[s].spec.name + "'");
    if (sensors[s].pose_known) mounts.known_mounts[s] = sensors[s].pose;
  }
  return mounts;
}

std::optional<HandEyeRig> RigDescription::handEye() const {
  HandEyeRig arm;
  arm.eye_in_hand = target.parent.empty() || target.parent == reference_frame;
  if (!arm.eye_in_hand) arm.tool_frame = target.parent;
  // A sensor behind joints makes an arm's rig when the board is not moved by hand (a pan-tilt head before
  // a hand-held board is calibrated in the graph of rigid sensors, JointedMounts).
  for (std::size_t s = 0; s < sensors.size(); ++s) {
    if (arm.tool_frame.empty() && !sensors[s].parent.empty() && (!behindJoints(static_cast<int>(s)) || !target.parent.empty())) {
      arm.tool_frame = sensors[s].parent;
    }
  }
  if (arm.tool_frame.empty()) return std::nullopt;
  arm.from_joints = isJointLink(arm.tool_frame);
  // The joints from the base to a link, empty when no chain leads there (readRigDescription refuses it).
  const auto chainTo = [&](const std::string& link) {
    try {
      return jointChain(joints, reference_frame, link, "link '" + link + "'");
    } catch (const InputError&) {
      return std::vector<int>();
    }
  };
  if (arm.from_joints) arm.chain = chainTo(arm.tool_frame);
  // With the board fixed, sensors on an arm's links before the tool (a forearm camera) beside those on
  // it: the tool is the link furthest along the chain (with the board on the tool, the board's link).
  for (std::size_t s = 0; s < sensors.size() && arm.from_joints && arm.eye_in_hand; ++s) {
    if (!behindJoints(static_cast<int>(s))) continue;
    std::vector<int> chain = chainTo(sensors[s].parent);
    if (chain.size() > arm.chain.size()) arm.tool_frame = sensors[s].parent, arm.chain = std::move(chain);
  }
  // Sensors on the other links the joints move: before the tool on its chain (a forearm camera), or on
  // another chain from the reference frame (a head's).
  arm.link_chains.assign(sensors.size(), {});
  for (std::size_t s = 0; s < sensors.size() && arm.from_joints; ++s) {
    if (sensors[s].parent.empty() || sensors[s].parent == arm.tool_frame || !behindJoints(static_cast<int>(s))) continue;
    arm.link_chains[s] = chainTo(sensors[s].parent);
  }
  // The main camera: the first on the other side from the board (on the tool itself when the board is
  // fixed), else the first on a link (a head's watching the board on the tool).
  for (std::size_t s = 0; s < sensors.size() && arm.camera < 0; ++s) {
    if (sensors[s].spec.type == SensorType::kCamera && sensors[s].parent.empty() != arm.eye_in_hand && arm.link_chains[s].empty())
      arm.camera = static_cast<int>(s);
  }
  for (std::size_t s = 0; s < sensors.size() && arm.camera < 0; ++s)
    if (sensors[s].spec.type == SensorType::kCamera && !arm.link_chains[s].empty()) arm.camera = static_cast<int>(s);
  return arm;
}

namespace {
// Reads `node[key]` as T, naming the key in the error.
template <typename T>
T required(const YAML::Node& node, const std::string& key, const std::string& where) {
  if (!node[key]) throw InputError(where + ": missing '" + key + "'");
  try {
    return node[key].as<T>();
  } catch (const YAML::Exception&) {
    throw InputError(where + ": '" + key + "' is malformed");
  }
}

void rejectUnknownKeys(const YAML::Node& node, const std::set<std::string>& known, const std::string& where) {
  for (const auto& entry : node) {
    const std::string key = yamlKeyName(entry.first, where);
    if (!known.count(key)) throw InputError(where + ": unknown key '" + key + "'");
  }
}

// `cameras_only`: the board's size may be left out (a camera sees only the pattern): the pattern's squares.
TargetDescription readTarget(const YAML::Node& node, const std::string& where, bool cameras_only) {
  if (!node.IsMap()) throw InputError(where + ": expected a map");
  rejectUnknownKeys(node, {"type", "rows", "cols", "square_size", "width", "height", "parent"}, where);
  const std::string type = required<std::string>(node, "type", where);
  if (type != "checkerboard") throw InputError(where + ": type '" + type + "' is not supported (checkerboard)");
  TargetDescription target;
  target.pattern.rows = required<int>(node, "rows", where);
  target.pattern.cols = required<int>(node, "cols", where);
  target.pattern.square_size = required<double>(node, "square_size", where);
  if (cameras_only && !node["width"] && !node["height"]) {
    target.width = (target.pattern.cols + 1) * target.pattern.square_size;
    target.height = (target.pattern.rows + 1) * target.pattern.square_size;
  } else {
    target.width = required<double>(node, "width", where);
    target.height = required<double>(node, "height", where);
  }
  if (node["parent"]) target.parent = required<std::string>(node, "parent", where);
  checkTargetDescription(target, where);
  return target;
}
}  // namespace

void checkTargetDescription(const TargetDescription& target, const std::string& where) {
  if (target.pattern.rows < 2 || target.pattern.cols < 2 || !(target.pattern.square_size > 0.0)) {
    throw InputError(where + ": rows and cols (inner corners) must be at least 2 and square_size positive");
  }
  const bool finite_size = std::isfinite(target.width) && std::isfinite(target.height);
  if (!(target.width > 0.0 && target.height > 0.0 && finite_size) ||
      (target.pattern.cols + 1) * target.pattern.square_size > target.width + 1e-9 ||
      (target.pattern.rows + 1) * target.pattern.square_size > target.height + 1e-9) {
    throw InputError(where + ": the " + std::to_string(target.pattern.rows + 1) + "x" + std::to_string(target.pattern.cols + 1) +
                     " squares do not fit on the " + std::to_string(target.width) + " x " + std::to_string(target.height) +
                     " m board");
  }
}

namespace {

Eigen::Isometry3d readPose(const YAML::Node& node, const std::string& where, const std::string& key = "pose") {
  std::vector<double> v;
  try {
    v = node.as<std::vector<double>>();
  } catch (const YAML::Exception&) {
    v.clear();
  }
  const Eigen::Quaterniond q = v.size() == 7 ? Eigen::Quaterniond(v[6], v[3], v[4], v[5]) : Eigen::Quaterniond::Identity();
  if (v.size() != 7 || !(std::abs(q.norm() - 1.0) < 1e-3) || !Eigen::Vector3d(v[0], v[1], v[2]).allFinite()) {
    throw InputError(where + ": '" + key + "' must be [x, y, z, qx, qy, qz, qw] with a unit quaternion");
  }
  return poseFromTranslationQuaternion(Eigen::Vector3d(v[0], v[1], v[2]), q);
}

// [xmin, ymin, zmin, xmax, ymax, zmax] in the sensor's frame, each min below its max.
CropBox readCropBox(const YAML::Node& node, const std::string& where) {
  std::vector<double> v;
  try {
    v = node.as<std::vector<double>>();
  } catch (const YAML::Exception&) {
    v.clear();
  }
  if (v.size() != 6 || !(v[0] < v[3] && v[1] < v[4] && v[2] < v[5])) {
    throw InputError(where + ": 'crop_box' must be [xmin, ymin, zmin, xmax, ymax, zmax] in the sensor's frame (metres, each min < max)");
  }
  CropBox box;
  box.min = Eigen::Vector3d(v[0], v[1], v[2]);
  box.max = Eigen::Vector3d(v[3], v[4], v[5]);
  return box;
}
}  // namespace

namespace {
// [x, y, z] as a vector, naming the key.
Eigen::Vector3d readVector3(const YAML::Node& node, const std::string& where) {
  std::vector<double> v;
  try {
    v = node.as<std::vector<double>>();
  } catch (const YAML::Exception&) {
    v.clear();
  }
  if (v.size() != 3 || !Eigen::Vector3d(v[0], v[1], v[2]).allFinite()) throw InputError(where + " must be [x, y, z]");
  return {v[0], v[1], v[2]};
}

std::vector<JointDescription> readJoints(const YAML::Node& list, const std::string& where) {
  if (!list.IsSequence()) throw InputError(where + ": expected a list of joints");
  std::vector<JointDescription> joints;
  std::set<std::string> names, children;
  for (std::size_t i = 0; i < list.size(); ++i) {
    const YAML::Node node = list[i];
    std::string at = where + "[" + std::to_string(i) + "]";
    if (!node.IsMap()) throw InputError(at + ": expected a map");
    JointDescription joint;
    joint.name = required<std::string>(node, "name", at);
    at += " '" + joint.name + "'";
    rejectUnknownKeys(node, {"name", "type", "parent", "child", "origin", "axis", "offset"}, at);
    joint.type = parseJointType(required<std::string>(node, "type", at), at);
    joint.parent = required<std::string>(node, "parent", at);
    joint.child = required<std::string>(node, "child", at);
    if (node["origin"]) joint.origin = readPose(node["origin"], at, "origin");
    if (node["axis"]) {
      const Eigen::Vector3d axis = readVector3(node["axis"], at + ": 'axis'");
      if (!(axis.norm() > 1e-9)) throw InputError(at + ": 'axis' is zero");
      joint.axis = axis.normalized();
    } else if (joint.type != JointType::kFixed) {
      throw InputError(at + ": missing 'axis'");
    }
    if (node["offset"]) joint.offset = required<double>(node, "offset", at);
    if (!std::isfinite(joint.offset)) throw InputError(at + ": 'offset' is not finite");
    if (!names.insert(joint.name).second) throw InputError(at + ": the name is used twice");
    if (!children.insert(joint.child).second) throw InputError(at + ": its child '" + joint.child + "' is another joint's child too");
    joints.push_back(joint);
  }
  return joints;
}

// What a hand-eye rig may be: one frame that moves (the tool), the board fixed in the reference frame or
// on the tool, a camera on the other side from the board, and no range sensor on the board's side (it
// would see the board in one place only).
void checkHandEyeRig(const RigDescription& rig, const HandEyeRig& arm, const std::string& path) {
  const bool board_on_tool = !arm.eye_in_hand;
  if (!rig.target.parent.empty() && rig.target.parent != rig.reference_frame && rig.target.parent != arm.tool_frame) {
    throw InputError(path + ": target: its parent '" + rig.target.parent + "' is neither " + rig.reference_frame + " nor the moving frame '" +
                     arm.tool_frame + "' a sensor is on; one moving frame per rig");
  }
  for (std::size_t s = 0; s < rig.sensors.size(); ++s) {
    const RigSensorDescription& sensor = rig.sensors[s];
    const std::string where = path + ": sensors[" + std::to_string(s) + "] '" + sensor.spec.name + "'";
    if (!sensor.parent.empty() && sensor.parent != arm.tool_frame && arm.link_chains[s].empty()) {
      throw InputError(where + ": its parent '" + sensor.parent + "' is a second moving frame besides '" + arm.tool_frame + "'" +
                       (arm.from_joints ? " and no chain of the joints leads to it" : "") + "; one moving frame per rig" +
                       (arm.from_joints ? "" : " (a sensor on an arm's other links needs the arm's joints: 'joints:' or 'urdf:')"));
    }
    const bool on_tool = !sensor.parent.empty();
    if (on_tool && rig.target.parent.empty()) {
      throw InputError(where + ": it is on the moving frame '" + arm.tool_frame +
                       "', so the board must stand still while the arm moves: give the target 'parent: " + rig.reference_frame + "'");
    }
    if (on_tool && board_on_tool && sensor.spec.type != SensorType::kCamera && arm.link_chains[s].empty()) {
      throw InputError(where + ": it is on the moving frame '" + arm.tool_frame + "' with the board, so it sees the board in one place "
                       "only, which fixes no " + sensorTypeName(sensor.spec.type));
    }
    if (!on_tool && !board_on_tool && sensor.spec.type != SensorType::kCamera) {
      throw InputError(where + ": it is fixed like the board, so it sees the board in one place only, which fixes no " +
                       sensorTypeName(sensor.spec.type) + ": put the board on the tool (target 'parent: " + arm.tool_frame + "')");
    }
  }
  if (arm.camera < 0) {
    throw InputError(path + ": a hand-eye rig needs a camera " +
                     (board_on_tool ? "fixed in " + rig.reference_frame + " watching the board on '" + arm.tool_frame + "'"
                                    : "on the moving frame '" + arm.tool_frame + "' watching the fixed board"));
  }
}
}  // namespace

namespace {
// What depends on the joints: the reference sensor (the first with a pose not behind joints), each jointed
// sensor's chain and known mount, and the hand-eye rig's checks.
void finishRig(RigDescription* rig_out, const std::string& path) {
  RigDescription& rig = *rig_out;
  for (const std::string& name : rig.free_joint_origins) {
    const auto joint = std::find_if(rig.joints.begin(), rig.joints.end(), [&](const JointDescription& j) { return j.name == name; });
    if (joint == rig.joints.end()) {
      std::string known;
      for (const JointDescription& j : rig.joints) known += (known.empty() ? "" : ", ") + j.name;
      throw InputError(path + ": 'free_joint_origins' names '" + name + "', which is no joint of the rig" +
                       (known.empty() ? std::string(" (it names none: give 'joints' or 'urdf')") : " (its joints: " + known + ")"));
    }
    joint->free_origin = true;
  }
  rig.reference_sensor = -1;
  for (std::size_t i = 0; i < rig.sensors.size(); ++i) {
    const RigSensorDescription& sensor = rig.sensors[i];
    const std::string where = path + ": sensors[" + std::to_string(i) + "] '" + sensor.spec.name + "'";
    const bool jointed = rig.behindJoints(static_cast<int>(i));
    // A sensor behind joints is never the reference: its pose is a mount in a moving link.
    if (sensor.pose && rig.reference_sensor < 0 && !jointed) rig.reference_sensor = static_cast<int>(i);
    if (sensor.pose_known && !(jointed && sensor.pose)) {
      throw InputError(where + ": 'pose_known' holds the 'pose' of a sensor behind joints (its mount in its parent link); " +
                       (jointed                ? std::string("give its 'pose'")
                        : sensor.parent.empty() ? std::string("it has no 'parent' link")
                                                : "its parent '" + sensor.parent + "' is no joint's child"));
    }
    if (jointed) jointChain(rig.joints, rig.reference_frame, sensor.parent, where);  // throws when no chain leads there
    // A rig that names joints moves its sensors by them, not by tf: a parent must be one of their links.
    const bool names_joints = !rig.joints.empty() || !rig.urdf.empty() || !rig.urdf_param.empty();
    if (names_joints && !sensor.parent.empty() && !jointed) {
      throw InputError(where + ": its parent '" + sensor.parent + "' is no link of the rig's joints" +
                       (rig.urdf_param.empty() ? std::string() : " (the URDF in " + rig.urdf_param + ")"));
    }
  }
  if (const std::optional<HandEyeRig> arm = rig.handEye()) {
    if (!rig.joints.empty() && !arm->from_joints) {
      throw InputError(path + ": a robot arm's tool frame from tf ('" + arm->tool_frame + "') and joints in one rig are not supported yet: "
                       "calibrate them in sessions of their own, or name the arm's joints down to its tool");
    }
    if (arm->from_joints) jointChain(rig.joints, rig.reference_frame, arm->tool_frame, path + ": the arm's tool");  // throws: no chain
    checkHandEyeRig(rig, *arm, path);
    rig.reference_sensor = -1;
    return;
  }

  if (rig.reference_sensor < 0 && rig.reference_imu >= 0) {
    // Its camera, placed through it once calibrated (calibrate_rig does the IMU first): the reference of
    // what the rig's still poses solve.
    rig.reference_sensor = rig.imus[rig.reference_imu].camera;
  }
  if (rig.reference_sensor < 0) {
    throw InputError(path + ": no sensor has a 'pose': give the reference sensor's pose in " + rig.reference_frame);
  }
  if (rig.sensors[rig.reference_sensor].spec.type == SensorType::kLaser2d) {
    throw InputError(path + ": the reference sensor '" + rig.sensors[rig.reference_sensor].spec.name +
                     "' (the first with a pose) is a 2D laser; give the pose of a sensor that sees the target's plane first");
  }
}
}  // namespace

namespace {
// An `imu` entry of sensors: its topic, noise figures and pose; returns the camera it names ("" for none).
std::string readImu(const YAML::Node& node, const std::string& name, const std::string& where, RigDescription* rig) {
  rejectUnknownKeys(node, {"name", "type", "frame_id", "imu_topic", "camera", "pose", "gyroscope_noise_density", "gyroscope_random_walk",
                           "accelerometer_noise_density", "accelerometer_random_walk"},
                    where);
  RigImuDescription imu;
  imu.name = name;
  imu.frame_id = required<std::string>(node, "frame_id", where);
  if (!node["imu_topic"]) throw InputError(where + ": an imu sensor needs 'imu_topic' (its sensor_msgs/Imu)");
  imu.imu_topic = required<std::string>(node, "imu_topic", where);
  const std::pair<const char*, double*> figures[] = {{"gyroscope_noise_density", &imu.noise.gyro_noise_density},
                                                     {"gyroscope_random_walk", &imu.noise.gyro_bias_random_walk},
                                                     {"accelerometer_noise_density", &imu.noise.accel_noise_density},
                                                     {"accelerometer_random_walk", &imu.noise.accel_bias_random_walk}};
  for (const auto& [key, value] : figures) {
    if (!node[key]) continue;
    *value = required<double>(node, key, where);
    if (!(*value > 0.0) || !std::isfinite(*value)) {
      throw InputError(where + ": '" + key + "' must be a positive number (got " + node[key].Scalar() + ")");
    }
  }
  if (node["pose"]) imu.pose = readPose(node["pose"], where);
  rig->imus.push_back(imu);
  return node["camera"] ? required<std::string>(node, "camera", where) : std::string();
}

// Each IMU's camera by name (default: the rig's first camera), and what an IMU may be in a rig.
void pairImusWithCameras(RigDescription* rig_out, const std::vector<std::string>& cameras, const std::string& path) {
  RigDescription& rig = *rig_out;
  for (std::size_t i = 0; i < rig.imus.size(); ++i) {
    RigImuDescription& imu = rig.imus[i];
    const std::string where = path + ": imu '" + imu.name + "'";
    for (std::size_t s = 0; s < rig.sensors.size() && imu.camera < 0; ++s) {
      const bool named = cameras[i].empty() || rig.sensors[s].spec.name == cameras[i];
      if (named && rig.sensors[s].spec.type == SensorType::kCamera) imu.camera = static_cast<int>(s);
    }
    if (imu.camera < 0) {
      throw InputError(where + ": " + (cameras[i].empty() ? std::string("the rig has no camera to calibrate it against (type: camera)")
                                                          : "its camera '" + cameras[i] + "' is no camera of the rig"));
    }
    // Placed through its camera, in the frame the camera is mounted in (a link or an arm's tool where it
    // moves); as the reference it would have to hold the still poses' frame, which a moving frame cannot.
    const bool moving_frames = !rig.joints.empty() || !rig.urdf.empty() || !rig.urdf_param.empty() || !rig.target.parent.empty();
    if (imu.pose && moving_frames) {
      throw InputError(where + ": its 'pose' makes it the reference of a rig with joints or an arm, which is not supported: give the pose of "
                       "a sensor fixed in " + rig.reference_frame + " (or none), and the IMU is placed through its camera");
    }
    if (imu.pose) {
      if (rig.reference_imu >= 0) throw InputError(where + ": two IMUs have a 'pose'; give one reference");
      for (const RigSensorDescription& sensor : rig.sensors) {
        if (sensor.pose && sensor.parent.empty()) {
          throw InputError(where + ": its 'pose' makes it the rig's reference, and so does the pose of sensor '" + sensor.spec.name +
                           "': give one reference's pose");
        }
      }
      rig.reference_imu = static_cast<int>(i);
    }
  }
}
}  // namespace

RigDescription readRigDescription(const std::string& path) {
  const YAML::Node root = loadYamlFile(path, "rig description");
  if (!root.IsMap()) throw InputError(path + ": expected a map with reference_frame, target and sensors");
  rejectUnknownKeys(root, {"reference_frame", "target", "sensors", "joints", "urdf", "urdf_param", "joint_states_topic", "free_joint_origins"},
                    path);
  RigDescription rig;
  rig.reference_frame = required<std::string>(root, "reference_frame", path);
  if (!root["target"]) throw InputError(path + ": missing 'target'");
  bool cameras_only = root["sensors"] && root["sensors"].IsSequence();
  if (cameras_only) {
    for (const YAML::Node& sensor : root["sensors"]) {
      cameras_only = cameras_only && sensor.IsMap() && sensor["type"] && sensor["type"].IsScalar() &&
                     (sensor["type"].Scalar() == "camera" || sensor["type"].Scalar() == "imu");
    }
  }
  rig.target = readTarget(root["target"], path + ": target", cameras_only);
  if (!!root["joints"] + !!root["urdf"] + !!root["urdf_param"] > 1) {
    throw InputError(path + ": give the joints in one of 'joints', 'urdf' (a file) or 'urdf_param' (a parameter), not several");
  }
  if (root["urdf_param"]) {
    rig.urdf_param = required<std::string>(root, "urdf_param", path);
    if (rig.urdf_param.empty()) throw InputError(path + ": 'urdf_param' is empty: name the parameter holding the URDF (/robot_description)");
  }
  if (root["joints"]) rig.joints = readJoints(root["joints"], path + ": joints");
  if (root["urdf"]) {
    rig.urdf = required<std::string>(root, "urdf", path);
    const std::size_t slash = path.find_last_of('/');
    rig.urdf_path = rig.urdf.front() == '/' || slash == std::string::npos ? rig.urdf : path.substr(0, slash + 1) + rig.urdf;
    rig.joints = readUrdfJoints(rig.urdf_path);
  }
  if (root["joint_states_topic"]) rig.joint_states_topic = required<std::string>(root, "joint_states_topic", path);
  if (root["free_joint_origins"]) {
    const YAML::Node list = root["free_joint_origins"];
    bool names = list.IsSequence();
    for (std::size_t i = 0; names && i < list.size(); ++i) names = list[i].IsScalar() && !list[i].Scalar().empty();
    if (!names) throw InputError(path + ": 'free_joint_origins' must list joint names, e.g. [elbow_joint, wrist_1_joint]");
    for (const YAML::Node& name : list) rig.free_joint_origins.push_back(name.Scalar());
  }
  if (!root["sensors"] || !root["sensors"].IsSequence() || root["sensors"].size() == 0) {
    throw InputError(path + ": 'sensors' must list at least one sensor");
  }
  std::set<std::string> names;
  std::vector<std::string> imu_cameras;  // per IMU, the camera named (empty: the first)
  rig.reference_sensor = -1;
  for (std::size_t i = 0; i < root["sensors"].size(); ++i) {
    const YAML::Node node = root["sensors"][i];
    std::string where = path + ": sensors[" + std::to_string(i) + "]";
    if (!node.IsMap()) throw InputError(where + ": expected a map");
    RigSensorDescription sensor;
    sensor.spec.name = required<std::string>(node, "name", where);
    where += " '" + sensor.spec.name + "'";
    if (!names.insert(sensor.spec.name).second) throw InputError(where + ": the name is used twice");
    if (node["type"] && node["type"].IsScalar() && node["type"].Scalar() == "imu") {
      imu_cameras.push_back(readImu(node, sensor.spec.name, where, &rig));
      continue;
    }
    rejectUnknownKeys(node, {"name", "type", "frame_id", "image_topic", "camera_info_topic", "depth_topic", "cloud_topic",
                             "scan_topic", "pose", "crop_box", "parent", "pose_known"},
                      where);
    try {
      sensor.spec.type = parseSensorType(required<std::string>(node, "type", where));
    } catch (const InputError& e) {
      throw InputError(where + ": " + e.what());
    }
    sensor.spec.frame_id = required<std::string>(node, "frame_id", where);
    auto topic = [&](const char* key, std::string* into, bool needed) {
      if (node[key]) *into = required<std::string>(node, key, where);
      if (needed && into->empty()) {
        throw InputError(where + ": a " + sensorTypeName(sensor.spec.type) + " sensor needs '" + key + "'");
      }
    };
    const SensorType type = sensor.spec.type;
    topic("image_topic", &sensor.image_topic, type == SensorType::kCamera);
    topic("camera_info_topic", &sensor.camera_info_topic, type == SensorType::kCamera || type == SensorType::kRgbd);
    topic("depth_topic", &sensor.depth_topic, type == SensorType::kRgbd);
    topic("cloud_topic", &sensor.cloud_topic, type == SensorType::kLidar3d);
    topic("scan_topic", &sensor.scan_topic, type == SensorType::kLaser2d);
    if (node["crop_box"]) {
      if (type == SensorType::kCamera) throw InputError(where + ": 'crop_box' is for range sensors (rgbd, lidar3d, laser2d), not cameras");
      sensor.crop_box = readCropBox(node["crop_box"], where);
    }
    if (node["parent"]) sensor.parent = required<std::string>(node, "parent", where);
    if (sensor.parent == rig.reference_frame) sensor.parent.clear();
    if (node["pose_known"]) sensor.pose_known = required<bool>(node, "pose_known", where);
    if (node["pose"]) sensor.pose = readPose(node["pose"], where);
    rig.sensors.push_back(sensor);
  }
  pairImusWithCameras(&rig, imu_cameras, path);
  // With the joints on the parameter server, the nodelet finishes the rig once it has read them (setRigJoints).
  if (rig.urdf_param.empty()) finishRig(&rig, path);
  return rig;
}

void setRigJoints(RigDescription* rig, std::vector<JointDescription> joints, const std::string& where) {
  rig->joints = std::move(joints);
  finishRig(rig, where);
}

void writeRigDescription(const std::string& path, const RigDescription& rig) {
  std::ofstream file(path);
  if (!file) throw InputError(path + ": cannot write rig description");
  const TargetPattern& p = rig.target.pattern;
  file << std::setprecision(10) << "reference_frame: " << rig.reference_frame << "\n"
       << "target: {type: checkerboard, rows: " << p.rows << ", cols: " << p.cols << ", square_size: " << p.square_size
       << ", width: " << rig.target.width << ", height: " << rig.target.height
       << (rig.target.parent.empty() ? "" : ", parent: " + rig.target.parent) << "}\n";
  const auto writePose = [&](const Eigen::Isometry3d& pose) {
    const Eigen::Vector3d t = pose.translation();
    const Eigen::Quaterniond q(pose.rotation());
    file << "[" << t.x() << ", " << t.y() << ", " << t.z() << ", " << q.x() << ", " << q.y() << ", " << q.z() << ", " << q.w() << "]";
  };
  if (rig.joint_states_topic != "/joint_states") file << "joint_states_topic: " << rig.joint_states_topic << "\n";
  if (!rig.free_joint_origins.empty()) {
    file << "free_joint_origins: [";
    for (std::size_t i = 0; i < rig.free_joint_origins.size(); ++i) file << (i ? ", " : "") << rig.free_joint_origins[i];
    file << "]\n";
  }
  if (!rig.urdf_param.empty()) {
    file << "urdf_param: " << rig.urdf_param << "\n";
  } else if (!rig.urdf.empty()) {
    file << "urdf: " << rig.urdf << "\n";
  } else if (!rig.joints.empty()) {
    file << "joints:\n";
    for (const JointDescription& joint : rig.joints) {
      file << "  - {name: " << joint.name << ", type: " << jointTypeName(joint.type) << ", parent: " << joint.parent << ", child: " << joint.child
           << ", offset: " << joint.offset << ",\n     origin: ";
      writePose(joint.origin);
      file << ", axis: [" << joint.axis.x() << ", " << joint.axis.y() << ", " << joint.axis.z() << "]}\n";
    }
  }
  file << "sensors:\n";
  for (const RigSensorDescription& s : rig.sensors) {
    file << "  - {name: " << s.spec.name << ", type: " << sensorTypeName(s.spec.type) << ", frame_id: " << s.spec.frame_id;
    if (!s.parent.empty()) file << ", parent: " << s.parent;
    const std::pair<const char*, const std::string*> topics[] = {{"image_topic", &s.image_topic},
                                                                 {"camera_info_topic", &s.camera_info_topic},
                                                                 {"depth_topic", &s.depth_topic},
                                                                 {"cloud_topic", &s.cloud_topic},
                                                                 {"scan_topic", &s.scan_topic}};
    for (const auto& topic : topics)
      if (!topic.second->empty()) file << ", " << topic.first << ": " << *topic.second;
    if (s.crop_box) {
      const CropBox& b = *s.crop_box;
      file << ", crop_box: [" << b.min.x() << ", " << b.min.y() << ", " << b.min.z() << ", " << b.max.x() << ", " << b.max.y()
           << ", " << b.max.z() << "]";
    }
    if (s.pose_known) file << ", pose_known: true";
    if (s.pose) {
      file << ",\n     pose: ";
      writePose(*s.pose);
    }
    file << "}\n";
  }
  for (const RigImuDescription& imu : rig.imus) {
    file << "  - {name: " << imu.name << ", type: imu, frame_id: " << imu.frame_id << ", imu_topic: " << imu.imu_topic
         << ", camera: " << rig.sensors.at(imu.camera).spec.name << ",\n     gyroscope_noise_density: " << imu.noise.gyro_noise_density
         << ", gyroscope_random_walk: " << imu.noise.gyro_bias_random_walk << ", accelerometer_noise_density: " << imu.noise.accel_noise_density
         << ", accelerometer_random_walk: " << imu.noise.accel_bias_random_walk;
    if (imu.pose) {
      file << ",\n     pose: ";
      writePose(*imu.pose);
    }
    file << "}\n";
  }
  if (!file) throw InputError(path + ": write failed");
}

}  // namespace vocal
