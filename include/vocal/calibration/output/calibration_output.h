#pragma once
// ---- MSG-Cal stage 4, output (calibration/output/): a result -> what a user applies and checks -------
// In:  CalibrationResult, the sensors' spread (PoseJackknife) and ring offsets.
// Out: which sensors are withheld and why; the result YAML, URDF snippet and static-transform launch
//      file (this file); each camera's view with the range sensors' board points drawn over it
//      (calibration_overlay.h).
// ------------------------------------------------------------------------------------------------------
//
// A calibration result as the files a ROS user applies: the result YAML of the design (per sensor:
// frame_id, parent, translation, rotation and their standard deviations), a URDF snippet of fixed
// joints, and a launch file of static transform publishers.

#include <optional>
#include <string>
#include <vector>

#include "vocal/calibration/calibration_types.h"
#include "vocal/calibration/extraction/lidar_ring_offsets.h"
#include "vocal/calibration/rig_description.h"
#include "vocal/calibration/solver/graph_calibration.h"
#include "vocal/calibration/solver/hand_eye_calibration.h"
#include "vocal/calibration/solver/pose_jackknife.h"

namespace vocal {

// Per sensor, why its result must stay out of /tf_static, the URDF and the launch file ("" where it may
// go in): the whole result is not trusted; or the sensor is not (SensorCalibration::distrust: it disagrees
// with the others), its spread across still poses is over `tolerance`, or there is no spread to judge it
// by (`spread` null) - these three unless `publish_uncertain`. The reference sensor, held fixed, goes in
// whenever the result is trusted.
std::vector<std::string> withheldSensors(const std::vector<SensorSpec>& sensors, int reference_sensor, const CalibrationResult& result,
                                         const PoseJackknife* spread, const SpreadTolerance& tolerance, bool publish_uncertain);

// Each throws InputError naming the file when it cannot be written. With `spread`, the YAML also gives
// each sensor's jackknife standard deviations over the still poses (translation_spread, rotation_spread);
// with `ring_offsets` (per sensor), each 3D lidar's range offset per ring and whether its board returns were
// corrected by them. With `withheld` (withheldSensors), the YAML marks each sensor published or not and
// why, and the URDF and launch file leave the withheld ones out (a comment says why). A sensor behind
// joints is written in its chain's last link (sensorParent); the YAML then gives each joint's offset with
// its sigma, and a `calibration:` block of the offsets as robot_calibration's calibration_offsets; the
// URDF names the <calibration rising="..."/> each joint needs.
void writeCalibrationYaml(const std::string& path, const std::string& reference_frame,
                          const std::vector<SensorSpec>& sensors, const CalibrationResult& result,
                          const PoseJackknife* spread = nullptr,
                          const std::vector<std::optional<RingOffsets>>* ring_offsets = nullptr,
                          const std::vector<std::string>* withheld = nullptr);
// A YAML double-quoted scalar of `text` (quotes and backslashes escaped).
std::string yamlQuoted(const std::string& text);
// One fixed URDF joint (with the child's link) and one static_transform_publisher node, as the files
// above write each sensor.
std::string urdfFixedJoint(const std::string& parent, const std::string& child, const Eigen::Isometry3d& parent_from_child);
std::string staticTransformNode(const std::string& name, const std::string& parent, const std::string& child,
                                const Eigen::Isometry3d& parent_from_child);
// A joint's offset for the user: "+12.95 mrad +- 0.25, moved 0.847 rad", then ", held: why" or ", weakly
// fixed ..." (mm and m for a prismatic joint); `width`: the offset's field width, for a table's column.
std::string jointOffsetText(const JointDescription& joint, const JointCalibration& calibration, int width = 0);
// A free origin as solved for the user: "origin xyz 0.0000 -0.0600 0.5012 rpy ...: solved shift along z
// +1.20 +- 0.30 mm, ...; held ..." (JointCalibration::origin_observability).
std::string jointOriginText(const JointCalibration& calibration);

// The frame sensor s's result is in: its chain's last link behind joints, else reference_frame.
std::string sensorParent(const CalibrationResult& result, std::size_t s, const std::string& reference_frame);
void writeUrdfSnippet(const std::string& path, const std::string& reference_frame, const std::vector<SensorSpec>& sensors,
                      const CalibrationResult& result, const std::vector<std::string>* withheld = nullptr);
void writeStaticTransformLaunch(const std::string& path, const std::string& reference_frame,
                                const std::vector<SensorSpec>& sensors, const CalibrationResult& result,
                                const std::vector<std::string>* withheld = nullptr);

// A hand-eye result (hand_eye_calibration.h) as the same three files: each sensor in its parent, the
// tool frame (on the tool) or the reference frame (fixed), as a user pastes it into the arm's URDF; the
// YAML also gives the board's pose, the poor arm poses and OpenCV's closed forms for the main camera.
struct HandEyeFrames {
  std::string reference_frame, tool_frame;
  std::vector<SensorSpec> sensors;
  std::vector<bool> on_tool;  // per sensor: moves with the arm (on the tool or on a link before it)
  std::vector<std::vector<int>> link_chains;  // per sensor: HandEyeRig::link_chains
  std::vector<std::string> parent_links;  // ... and that link's name (empty for the others)
  // Per sensor, the pose the rig gives that the solve holds: the first fixed sensor's with a `pose` (the
  // reference, in reference_frame) and a tool sensor's `pose_known` mount.
  std::vector<std::optional<Eigen::Isometry3d>> given_poses;
  std::vector<std::string> joint_names;  // an arm whose tool comes from its joints: those read (HandEyeRig::readJoints), in order
  const std::string& parentOf(std::size_t sensor) const {
    return !parent_links[sensor].empty() ? parent_links[sensor] : on_tool[sensor] ? tool_frame : reference_frame;
  }
  std::vector<HandEyeSensor> solverSensors() const;  // what calibrateArmRig takes
};
// A hand-eye rig's frames (`arm`: rig.handEye()).
HandEyeFrames handEyeFrames(const RigDescription& rig, const HandEyeRig& arm);
// Why a sensor stays out of the URDF and launch file ("" where it may go in): it moved part-way through
// the session (HandEyeResult::placement_changes: always), or its spread across the arm's poses is over
// `tolerance`, or none could be computed - unless `publish_uncertain`; what to record more of, by the
// sensor's `type`.
std::string handEyeWithheld(const HandEyeResult& result, std::size_t sensor, SensorType type, const SpreadTolerance& tolerance,
                            bool publish_uncertain);
// `withheld`: per sensor, handEyeWithheld.
void writeHandEyeYaml(const std::string& path, const HandEyeFrames& frames, const HandEyeResult& result, const std::vector<std::string>& withheld);
void writeHandEyeUrdf(const std::string& path, const HandEyeFrames& frames, const HandEyeResult& result, const std::vector<std::string>& withheld);
void writeHandEyeLaunch(const std::string& path, const HandEyeFrames& frames, const HandEyeResult& result, const std::vector<std::string>& withheld);

}  // namespace vocal
