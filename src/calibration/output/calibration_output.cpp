#include "vocal/calibration/output/calibration_output.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iomanip>
#include <sstream>

#include "vocal/core/errors.h"
#include "vocal/core/se3.h"

namespace vocal {

namespace {
std::ofstream openOutput(const std::string& path) {
  std::ofstream file(path);
  if (!file) throw InputError(path + ": cannot write calibration output");
  file << std::setprecision(9);
  return file;
}

void finish(std::ofstream& file, const std::string& path) {
  if (!file.flush()) throw InputError(path + ": write error");
}

void checkSizes(const std::vector<SensorSpec>& sensors, const CalibrationResult& result) {
  if (sensors.size() != result.sensors.size()) {
    throw InputError("calibration output: " + std::to_string(sensors.size()) + " sensors but " +
                     std::to_string(result.sensors.size()) + " results");
  }
}
std::string listOf(const Eigen::Ref<const Eigen::VectorXd>& v) {
  std::ostringstream out;
  out << std::setprecision(9) << "[";
  for (Eigen::Index i = 0; i < v.size(); ++i) out << (i ? ", " : "") << v[i];
  out << "]";
  return out.str();
}

// The reason sensor s is withheld, empty when it is published (or nothing was withheld).
std::string withheldReason(const std::vector<std::string>* withheld, std::size_t s) {
  return withheld && s < withheld->size() ? (*withheld)[s] : std::string();
}
}  // namespace

std::string yamlQuoted(const std::string& text) {
  std::string out = "\"";
  for (const char c : text) out += c == '"' || c == '\\' ? std::string("\\") + c : std::string(1, c);
  return out + "\"";
}

namespace {
// A camera's intrinsics refined with the poses, as a sensor entry's `intrinsics:` block.
std::string refinedIntrinsicsYaml(const Eigen::Vector4d& given, const Eigen::Vector4d& refined, const Eigen::Vector4d& sigma) {
  return "    intrinsics:  # fx fy cx cy, px: refined with the poses (--refine-intrinsics); the refined ones go in its camera_info's K\n"
         "      given: " + listOf(given) + "\n      refined: " + listOf(refined) + "\n      stddev: " + listOf(sigma) + "\n";
}

// A free joint origin as solved, a YAML flow map: the origin (xyz m, rpy rad), its correction from the
// model's and standard deviations (turn about x y z in rad, shift along x y z in m; zero: held), what fixed it.
std::string freeOriginYaml(const JointCalibration& joint) {
  const Eigen::Vector3d t = joint.origin.translation(), rpy = rollPitchYawFromRotation(joint.origin.rotation());
  return "{xyz: " + listOf(t) + ", rpy: " + listOf(rpy) + ", correction: " + listOf(joint.origin_correction) +
         ", correction_stddev: " + listOf(joint.origin_sigma) + ", observability: " + yamlQuoted(joint.origin_observability) + "}";
}
}  // namespace

std::vector<std::string> withheldSensors(const std::vector<SensorSpec>& sensors, int reference_sensor, const CalibrationResult& result,
                                         const PoseJackknife* spread, const SpreadTolerance& tolerance, bool publish_uncertain) {
  std::vector<std::string> withheld(sensors.size());
  for (std::size_t s = 0; s < sensors.size(); ++s) {
    if (!result.trusted) {
      withheld[s] = "the calibration is not trusted (" + result.failure + ")";
    } else if (static_cast<int>(s) == reference_sensor || publish_uncertain) {
      continue;
    } else if (s < result.sensors.size() && !result.sensors[s].distrust.empty()) {
      withheld[s] = "not trusted: " + result.sensors[s].distrust;
    } else if (!spread || s >= spread->standard_deviation.size()) {
      withheld[s] = "uncertain: its spread across still poses could not be computed, so nothing says the result holds";
    } else if (spreadIsOver(spread->standard_deviation[s], tolerance)) {
      char line[160];
      std::snprintf(line, sizeof(line), "uncertain: it moves %.1f mm / %.1f mrad between re-solves without one pose (tolerance %.1f mm / %.1f mrad)",
                    1000 * spread->standard_deviation[s].head<3>().norm(), 1000 * spread->standard_deviation[s].tail<3>().norm(),
                    1000 * tolerance.translation, 1000 * tolerance.rotation);
      withheld[s] = line;
    }
  }
  return withheld;
}

void writeCalibrationYaml(const std::string& path, const std::string& reference_frame,
                          const std::vector<SensorSpec>& sensors, const CalibrationResult& result, const PoseJackknife* spread,
                          const std::vector<std::optional<RingOffsets>>* ring_offsets, const std::vector<std::string>* withheld) {
  checkSizes(sensors, result);
  std::ofstream file = openOutput(path);
  file << "# vocal MSG-Cal result: pose of each sensor frame in " << reference_frame << "\n"
       << "reference_frame: " << reference_frame << "\n"
       << "rms_m: " << result.rms << "\n"
       << "sensors:\n";
  for (std::size_t s = 0; s < sensors.size(); ++s) {
    const SensorCalibration& c = result.sensors[s];
    const Eigen::Vector3d t = c.reference_from_sensor.translation();
    const Eigen::Quaterniond q(c.reference_from_sensor.rotation());
    // Honest: the larger of the solver's sigma (every point's error independent) and the spread across
    // still poses (errors a pose's points share), axis by axis.
    const bool has_spread = spread && s < spread->standard_deviation.size();
    const Vector6d sd = has_spread ? c.standard_deviation.cwiseMax(spread->standard_deviation[s]) : c.standard_deviation;
    file << "  - name: " << sensors[s].name << "\n"
         << "    type: " << sensorTypeName(sensors[s].type) << "\n"
         << "    frame_id: " << sensors[s].frame_id << "\n"
         << "    parent: " << sensorParent(result, s, reference_frame) << "\n"
         << "    translation: [" << t.x() << ", " << t.y() << ", " << t.z() << "]\n"
         << "    rotation: [" << q.x() << ", " << q.y() << ", " << q.z() << ", " << q.w() << "]\n"
         << "    translation_stddev: [" << sd[0] << ", " << sd[1] << ", " << sd[2] << "]"
         << (has_spread ? "  # m, the larger of the solver's and the spread across still poses\n" : "  # m, the solver's\n")
         << "    rotation_stddev: [" << sd[3] << ", " << sd[4] << ", " << sd[5] << "]  # rad, about x y z\n"
         << "    solver_translation_stddev: [" << c.standard_deviation[0] << ", " << c.standard_deviation[1] << ", " << c.standard_deviation[2] << "]\n"
         << "    solver_rotation_stddev: [" << c.standard_deviation[3] << ", " << c.standard_deviation[4] << ", " << c.standard_deviation[5] << "]\n"
         << "    trusted: " << (c.distrust.empty() && result.trusted ? "true" : "false") << "\n";
    if (!c.distrust.empty()) file << "    not_trusted_because: " << yamlQuoted(c.distrust) << "\n";
    if (c.isolated) file << "    isolated: true  # kept out of the graph: the others were solved without it\n";
    if (c.compared_poses > 0) {
      file << "    disagreement: {distance_m: " << c.disagreement_distance << ", angle_rad: " << c.disagreement_angle
           << ", poses: " << c.compared_poses << "}  # median, its board views against the board the others solved\n";
    }
    if (withheld) {
      const std::string why = withheldReason(withheld, s);
      file << "    published: " << (why.empty() ? "true" : "false") << "\n";
      if (!why.empty()) file << "    withheld_because: " << yamlQuoted(why) << "\n";
    }
    if (c.intrinsicsRefined()) file << refinedIntrinsicsYaml(c.given_intrinsics, c.refined_intrinsics, c.intrinsics_sigma);
    if (spread && s < spread->standard_deviation.size()) {
      const Vector6d& jk = spread->standard_deviation[s];
      file << "    translation_spread: [" << jk[0] << ", " << jk[1] << ", " << jk[2] << "]  # m, jackknife over still poses\n"
           << "    rotation_spread: [" << jk[3] << ", " << jk[4] << ", " << jk[5] << "]  # rad, jackknife over still poses\n";
    }
    if (ring_offsets && s < ring_offsets->size() && (*ring_offsets)[s]) {
      const RingOffsets& rings = *(*ring_offsets)[s];
      const auto list = [&](const char* key, auto value, const char* comment) {
        file << "      " << key << ": [";
        for (std::size_t r = 0; r < rings.elevations.size(); ++r) file << (r ? ", " : "") << value(r);
        file << "]" << comment << "\n";
      };
      file << "    ring_offsets:  # from " << rings.planes << " room planes; applied: the board's returns were moved back along their rays by them\n"
           << "      applied: " << (rings.applied ? "true" : "false") << "\n"
           << "      verdict: " << yamlQuoted(rings.verdict) << "\n";
      if (!rings.warning.empty()) file << "      warning: " << yamlQuoted(rings.warning) << "\n";
      file << "      common_offset_m: " << rings.common_offset << "  # one offset for all rings, the room's planes one by one (median)\n"
           << "      planes_agreeing: " << rings.planes_agreeing << "  # their share within " << rings.agreement << " m of it\n";
      list("elevation_deg", [&](std::size_t r) { return rings.elevations[r] * 180.0 / M_PI; }, "");
      list("offset_m", [&](std::size_t r) { return rings.offsets[r]; }, "  # how much too long each ring's ranges read");
      list("offset_stddev_m", [&](std::size_t r) { return rings.sigmas[r]; }, "");
    }
    file << "    rms_m: " << c.rms << "\n"
         << "    observations: " << c.observations << "\n";
  }
  if (result.board_mount) {
    // The board on a frame that moves (an arm's tool), or lying still in the base: its mount there, the solver's sigma.
    const Eigen::Vector3d t = result.board_mount->translation();
    const Eigen::Quaterniond q(result.board_mount->rotation());
    const Vector6d& sd = result.board_mount_sigma;
    const std::vector<int>& chain = result.mounts.board_chain;
    const std::string parent = result.mounts.board_fixed ? reference_frame
                               : !chain.empty()           ? result.mounts.joints.at(chain.back()).child
                                                          : result.mounts.tool_frame;
    file << "board:  # the board's mount on the frame that holds it, or in the base where it lay still\n";
    if (!parent.empty()) file << "  parent: " << parent << "\n";
    file << "  translation: [" << t.x() << ", " << t.y() << ", " << t.z() << "]\n"
         << "  rotation: [" << q.x() << ", " << q.y() << ", " << q.z() << ", " << q.w() << "]\n"
         << "  translation_stddev: [" << sd[0] << ", " << sd[1] << ", " << sd[2] << "]  # m, the solver's\n"
         << "  rotation_stddev: [" << sd[3] << ", " << sd[4] << ", " << sd[5] << "]  # rad, about x y z\n";
    const Eigen::Vector3d& print = result.print_on_board;
    file << "  print: [" << print.x() << ", " << print.y() << ", " << print.z()
         << "]  # the pattern on the board: m along its x and y from its centre, rad about its normal (zero: not solved, or nothing saw its edges)\n";
  }
  if (result.mounts.boardMoves()) {  // an arm's session
    file << "poor_still_poses: [";
    for (std::size_t i = 0; i < result.poor_arm_poses.size(); ++i) file << (i ? ", " : "") << result.poor_arm_poses[i];
    file << "]  # numbered from 0: still poses the arm had to move beyond its repeatability to fit the others (they do not pull the result)\n";
  }
  if (result.view_scatter) {
    file << "unmodelled: {translation_m: " << result.view_scatter->translation << ", rotation_rad: " << result.view_scatter->rotation
         << "}  # per axis, added to every camera view's covariance (zero: the views' noise and the arm's repeatability explained them)\n";
  }
  if (!result.mounts.chains.empty() || !result.mounts.board_chain.empty()) {
    // Each joint a sensor or the board is behind: its zero offset (added to the encoder's reading), and robot_calibration's block of them.
    file << "joints:  # offsets added to each joint's reading (radians; metres for a prismatic joint)\n";
    for (std::size_t j = 0; j < result.joints.size() && j < result.mounts.joints.size(); ++j) {
      const JointCalibration& joint = result.joints[j];
      if (!joint.reported) continue;
      file << "  - name: " << result.mounts.joints[j].name << "\n"
           << "    offset: " << joint.offset << "\n"
           << "    offset_stddev: " << joint.standard_deviation << "\n"
           << "    motion: " << joint.motion << "  # the range its readings covered over the still poses\n"
           << "    solved: " << (joint.held.empty() ? "true" : "false") << "\n";
      if (!joint.held.empty()) file << "    held_because: " << yamlQuoted(joint.held) << "\n";
      if (!joint.fixed_by.empty()) file << "    fixed_by: " << yamlQuoted(joint.fixed_by) << "\n";
      if (!joint.weak.empty()) file << "    weak: " << yamlQuoted(joint.weak) << "\n";
      if (joint.origin_free) file << "    origin: " << freeOriginYaml(joint) << "  # its correction: turn about x y z (rad), shift along x y z (m)\n";
    }
    file << "calibration:  # robot_calibration's calibration_offsets\n";
    for (std::size_t j = 0; j < result.joints.size() && j < result.mounts.joints.size(); ++j)
      if (result.joints[j].held.empty()) file << "  " << result.mounts.joints[j].name << ": " << result.joints[j].offset << "\n";
  }
  finish(file, path);
}

std::string jointOffsetText(const JointDescription& joint, const JointCalibration& calibration, int width) {
  const bool prismatic = JointTolerances::prismatic(joint);
  char line[160];
  std::snprintf(line, sizeof(line), "%+*.2f %s +- %.2f, moved %.3f %s", width, 1000 * calibration.offset, prismatic ? "mm" : "mrad",
                1000 * calibration.standard_deviation, calibration.motion, prismatic ? "m" : "rad");
  std::string text = line;
  if (!calibration.held.empty()) text += ", held: " + calibration.held;
  if (!calibration.fixed_by.empty()) text += ", fixed by " + calibration.fixed_by;
  if (!calibration.weak.empty()) text += ", " + calibration.weak;
  return text;
}

std::string jointOriginText(const JointCalibration& calibration) {
  const Eigen::Vector3d t = calibration.origin.translation(), rpy = rollPitchYawFromRotation(calibration.origin.rotation());
  char line[160];
  std::snprintf(line, sizeof(line), "origin xyz %.5f %.5f %.5f rpy %.5f %.5f %.5f: ", t.x(), t.y(), t.z(), rpy.x(), rpy.y(), rpy.z());
  return line + calibration.origin_observability;
}

std::string sensorParent(const CalibrationResult& result, std::size_t s, const std::string& reference_frame) {
  if (result.mounts.onReportedTool(static_cast<int>(s))) return result.mounts.tool_frame;
  if (!result.mounts.jointed(static_cast<int>(s))) return reference_frame;
  return result.mounts.joints.at(result.mounts.chains[s].back()).child;
}

std::string urdfFixedJoint(const std::string& parent, const std::string& child, const Eigen::Isometry3d& parent_from_child) {
  // URDF rpy: fixed axes, R = Rz(yaw) Ry(pitch) Rx(roll).
  const Eigen::Vector3d rpy = rollPitchYawFromRotation(parent_from_child.rotation());
  const Eigen::Vector3d t = parent_from_child.translation();
  std::ostringstream out;
  out << "<link name=\"" << child << "\"/>\n"
      << "<joint name=\"" << parent << "_to_" << child << "\" type=\"fixed\">\n"
      << "  <parent link=\"" << parent << "\"/>\n"
      << "  <child link=\"" << child << "\"/>\n"
      << "  <origin xyz=\"" << t.x() << " " << t.y() << " " << t.z() << "\" rpy=\"" << rpy[0] << " " << rpy[1] << " " << rpy[2] << "\"/>\n"
      << "</joint>\n";
  return out.str();
}

std::string staticTransformNode(const std::string& name, const std::string& parent, const std::string& child,
                                const Eigen::Isometry3d& parent_from_child) {
  const Eigen::Vector3d t = parent_from_child.translation();
  const Eigen::Quaterniond q(parent_from_child.rotation());
  std::ostringstream out;
  out << "  <node pkg=\"tf2_ros\" type=\"static_transform_publisher\" name=\"" << name << "\" args=\"" << t.x() << " " << t.y() << " "
      << t.z() << " " << q.x() << " " << q.y() << " " << q.z() << " " << q.w() << " " << parent << " " << child << "\"/>\n";
  return out.str();
}

void writeUrdfSnippet(const std::string& path, const std::string& reference_frame, const std::vector<SensorSpec>& sensors,
                      const CalibrationResult& result, const std::vector<std::string>* withheld) {
  checkSizes(sensors, result);
  std::ofstream file = openOutput(path);
  file << "<!-- vocal MSG-Cal result: paste into the robot's URDF -->\n";
  for (std::size_t s = 0; s < sensors.size(); ++s) {
    if (const std::string why = withheldReason(withheld, s); !why.empty()) {
      file << "<!-- " << sensors[s].frame_id << " withheld: " << why << " (see calibration.yaml) -->\n";
      continue;
    }
    file << urdfFixedJoint(sensorParent(result, s, reference_frame), sensors[s].frame_id, result.sensors[s].reference_from_sensor);
  }
  for (std::size_t j = 0; j < result.joints.size() && j < result.mounts.joints.size(); ++j) {
    if (!result.joints[j].held.empty()) continue;
    file << "<!-- joint " << result.mounts.joints[j].name << ": its reading's zero is off by " << result.joints[j].offset
         << "; in its <joint>: <calibration rising=\"" << result.joints[j].offset << "\"/>, or add it to the driver's reading -->\n";
  }
  finish(file, path);
}

void writeStaticTransformLaunch(const std::string& path, const std::string& reference_frame,
                                const std::vector<SensorSpec>& sensors, const CalibrationResult& result,
                                const std::vector<std::string>* withheld) {
  checkSizes(sensors, result);
  std::ofstream file = openOutput(path);
  file << "<launch>\n  <!-- vocal MSG-Cal result as static transforms -->\n";
  for (std::size_t s = 0; s < sensors.size(); ++s) {
    if (const std::string why = withheldReason(withheld, s); !why.empty()) {
      file << "  <!-- " << sensors[s].frame_id << " withheld: " << why << " (see calibration.yaml) -->\n";
      continue;
    }
    file << staticTransformNode(sensors[s].name + "_extrinsic", sensorParent(result, s, reference_frame), sensors[s].frame_id,
                                result.sensors[s].reference_from_sensor);
  }
  file << "</launch>\n";
  finish(file, path);
}

namespace {

}  // namespace

HandEyeFrames handEyeFrames(const RigDescription& rig, const HandEyeRig& arm) {
  HandEyeFrames frames{rig.reference_frame, arm.tool_frame, rig.specs(), {}, {}, {}, {}, {}};
  if (arm.from_joints)
    for (const int j : arm.readJoints()) frames.joint_names.push_back(rig.joints.at(j).name);
  bool reference_given = false;
  for (std::size_t s = 0; s < rig.sensors.size(); ++s) {
    const RigSensorDescription& d = rig.sensors[s];
    const bool on_tool = !d.parent.empty();
    frames.on_tool.push_back(on_tool);
    frames.link_chains.push_back(s < arm.link_chains.size() ? arm.link_chains[s] : std::vector<int>());
    frames.parent_links.push_back(frames.link_chains.back().empty() ? std::string() : d.parent);
    const bool reference = !on_tool && d.pose && !reference_given;
    reference_given = reference_given || reference;
    frames.given_poses.push_back(reference || (on_tool && d.pose_known) ? d.pose : std::nullopt);
  }
  return frames;
}

std::vector<HandEyeSensor> HandEyeFrames::solverSensors() const {
  std::vector<HandEyeSensor> out;
  for (std::size_t s = 0; s < sensors.size(); ++s) {
    out.push_back({sensors[s].type, on_tool[s], given_poses[s], sensors[s].name});
    out.back().link_chain = link_chains[s];
  }
  return out;
}

std::string handEyeWithheld(const HandEyeResult& result, std::size_t sensor, SensorType type, const SpreadTolerance& tolerance,
                            bool publish_uncertain) {
  char line[420];
  // Moved, not uncertain: no number of poses makes it right, so it is withheld even when uncertain ones are not.
  if (sensor < result.placement_changes.size() && result.placement_changes[sensor].station >= 0) {
    const HandEyePlacementChange& change = result.placement_changes[sensor];
    std::snprintf(line, sizeof(line),
                  "it moved part-way through the session: its placement from the arm poses before pose %d and from those after "
                  "differ by %.1f mm / %.1f mrad, %.0f times their sigmas (bumped, or a loose mount); fix it and record again",
                  change.station + 1, 1000 * change.translation, 1000 * change.rotation, change.sigmas);
    return line;
  }
  if (publish_uncertain) return "";
  if (result.spread_solves < 2) {
    std::snprintf(line, sizeof(line), "no spread across the arm's poses could be computed (%d re-solves without one pose): add poses",
                  result.spread_solves);
    return line;
  }
  const Vector6d& spread = result.sensor_spreads[sensor];
  if (!spreadIsOver(spread, tolerance)) return "";
  std::snprintf(line, sizeof(line),
                "uncertain: it moves %.1f mm / %.1f mrad between re-solves without one arm pose (tolerance %.1f mm / %.1f mrad): add "
                "%s",
                1000 * spread.head<3>().norm(), 1000 * spread.tail<3>().norm(), 1000 * tolerance.translation, 1000 * tolerance.rotation,
                // A 2D laser's line fixes little where every pose crosses the board at one place and slant.
                type == SensorType::kLaser2d ? "arm poses whose scan line crosses the board at other places and slants, near its edges too"
                                             : "arm poses, turned further about more axes");
  return line;
}

void writeHandEyeYaml(const std::string& path, const HandEyeFrames& frames, const HandEyeResult& result, const std::vector<std::string>& withheld) {
  std::ofstream file = openOutput(path);
  const std::string board_parent = result.setup == HandEyeSetup::kEyeInHand ? frames.reference_frame : frames.tool_frame;
  const auto pose = [&](const Eigen::Isometry3d& p, const Vector6d& sd, const char* indent) {
    const Eigen::Vector3d t = p.translation();
    const Eigen::Quaterniond q(p.rotation());
    file << indent << "translation: [" << t.x() << ", " << t.y() << ", " << t.z() << "]\n"
         << indent << "rotation: [" << q.x() << ", " << q.y() << ", " << q.z() << ", " << q.w() << "]\n"
         << indent << "translation_stddev: " << listOf(sd.head<3>()) << "  # m\n"
         << indent << "rotation_stddev: " << listOf(sd.tail<3>()) << "  # rad, about x y z\n";
  };
  file << "# vocal hand-eye result (" << handEyeSetupName(result.setup) << "): each sensor in its parent, the tool frame "
       << frames.tool_frame << " or " << frames.reference_frame << "; the board in " << board_parent << "\n"
       << "reference_frame: " << frames.reference_frame << "\n"
       << "setup: " << handEyeSetupName(result.setup) << "\n"
       << "tool_frame: " << frames.tool_frame << "\n"
       << "sensors:\n";
  for (std::size_t s = 0; s < frames.sensors.size(); ++s) {
    file << "  - name: " << frames.sensors[s].name << "\n"
         << "    type: " << sensorTypeName(frames.sensors[s].type) << "\n"
         << "    frame_id: " << frames.sensors[s].frame_id << "\n"
         << "    parent: " << frames.parentOf(s) << "\n";
    // Honest: the larger of the solver's sigma and the spread across the arm's poses, axis by axis.
    pose(result.sensors[s], result.sensor_sigmas[s].cwiseMax(result.sensor_spreads[s]), "    ");
    file << "    solver_translation_stddev: " << listOf(result.sensor_sigmas[s].head<3>()) << "\n"
         << "    solver_rotation_stddev: " << listOf(result.sensor_sigmas[s].tail<3>()) << "\n"
         << "    translation_spread: " << listOf(result.sensor_spreads[s].head<3>()) << "  # m, jackknife over the arm's poses\n"
         << "    rotation_spread: " << listOf(result.sensor_spreads[s].tail<3>()) << "  # rad\n"
         << "    published: " << (withheld[s].empty() ? "true" : "false") << "\n";
    if (s < result.given_intrinsics.size() && !result.given_intrinsics[s].isZero())
      file << refinedIntrinsicsYaml(result.given_intrinsics[s], result.refined_intrinsics[s], result.intrinsics_sigma[s]);
    if (s < result.held.size() && result.held[s]) file << "    held: true  # at the pose the rig gives\n";
    if (!withheld[s].empty()) file << "    withheld_because: " << yamlQuoted(withheld[s]) << "\n";
  }
  file << "target:\n"
       << "  parent: " << board_parent << "\n";
  pose(result.board, result.board_sigma, "  ");
  file << "arm_poses: " << result.tool_shift.size() << "\n"
       << "poor_arm_poses: [";
  for (std::size_t i = 0; i < result.poor_stations.size(); ++i) file << (i ? ", " : "") << result.poor_stations[i] + 1;
  file << "]  # numbered from 1: the tool had to move beyond the arm's repeatability to fit\n"
       << "board_rms: {distance_m: " << result.rms_distance << ", angle_rad: " << result.rms_angle << "}  # each camera view against the solution\n"
       << "unmodelled: {translation_m: " << result.unmodelled_translation << ", rotation_rad: " << result.unmodelled_rotation
       << "}  # per axis, added to every camera view's covariance\n"
       << "closed_forms:  # OpenCV's calibrateHandEye on the same poses, for " << frames.sensors[result.main_camera].name << "\n";
  for (const HandEyeClosedForm& c : result.closed_forms) {
    const Eigen::Vector3d t = c.camera.translation();
    const Eigen::Quaterniond q(c.camera.rotation());
    file << "  - {method: " << c.method << ", translation: [" << t.x() << ", " << t.y() << ", " << t.z() << "], rotation: [" << q.x() << ", "
         << q.y() << ", " << q.z() << ", " << q.w() << "]}\n";
  }
  if (!result.joints.empty() && result.joints.size() == frames.joint_names.size()) {
    const bool any_origin = std::any_of(result.joints.begin(), result.joints.end(), [](const JointCalibration& j) { return j.origin_free; });
    file << "joints:  # the arm's chain, then other links' (a head's): offsets added to each joint's reading (radians; metres for a prismatic joint)\n";
    if (any_origin) file << "         # a free origin as solved, its correction from the model's: turn about x y z (rad), shift along x y z (m)\n";
    for (std::size_t i = 0; i < result.joints.size(); ++i) {
      const JointCalibration& joint = result.joints[i];
      if (!joint.reported) continue;
      file << "  - {name: " << frames.joint_names[i] << ", offset: " << joint.offset << ", offset_stddev: " << joint.standard_deviation
           << ", motion: " << joint.motion << ", solved: " << (joint.held.empty() ? "true" : "false");
      if (!joint.fixed_by.empty()) file << ", fixed_by: " << yamlQuoted(joint.fixed_by);
      if (joint.origin_free) file << ",\n     origin: " << freeOriginYaml(joint);
      file << "}\n";
    }
    file << "calibration:  # robot_calibration's calibration_offsets\n";
    for (std::size_t i = 0; i < result.joints.size(); ++i)
      if (result.joints[i].held.empty()) file << "  " << frames.joint_names[i] << ": " << result.joints[i].offset << "\n";
  }
  finish(file, path);
}

void writeHandEyeUrdf(const std::string& path, const HandEyeFrames& frames, const HandEyeResult& result, const std::vector<std::string>& withheld) {
  std::ofstream file = openOutput(path);
  file << "<!-- vocal hand-eye result: paste into the robot's URDF -->\n";
  for (std::size_t s = 0; s < frames.sensors.size(); ++s) {
    if (withheld[s].empty()) {
      file << urdfFixedJoint(frames.parentOf(s), frames.sensors[s].frame_id, result.sensors[s]);
    } else {
      file << "<!-- " << frames.sensors[s].frame_id << " withheld: " << withheld[s] << " (see calibration.yaml) -->\n";
    }
  }
  finish(file, path);
}

void writeHandEyeLaunch(const std::string& path, const HandEyeFrames& frames, const HandEyeResult& result, const std::vector<std::string>& withheld) {
  std::ofstream file = openOutput(path);
  file << "<launch>\n  <!-- vocal hand-eye result as static transforms -->\n";
  for (std::size_t s = 0; s < frames.sensors.size(); ++s) {
    if (withheld[s].empty()) {
      file << staticTransformNode(frames.sensors[s].name + "_extrinsic", frames.parentOf(s), frames.sensors[s].frame_id, result.sensors[s]);
    } else {
      file << "  <!-- " << frames.sensors[s].frame_id << " withheld: " << withheld[s] << " (see calibration.yaml) -->\n";
    }
  }
  file << "</launch>\n";
  finish(file, path);
}

}  // namespace vocal
