// calibrate_rig RIG.yaml BAG [options, see kUsage]: MSG-Cal on a recorded session. Reads
// every message on the rig's topics, extracts the target per sensor, associates the still periods,
// calibrates, prints each sensor's extrinsic with its standard deviation (the solver's, and the spread across
// still poses) and residual, and writes the result YAML, a URDF snippet and a static-transform launch file.

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <functional>
#include <iomanip>
#include <map>
#include <optional>
#include <string>

#include <unistd.h>

#include "vocal/calibration/calibration_session.h"
#include "vocal/calibration/output/calibrated_urdf.h"
#include "vocal/calibration/output/calibration_output.h"
#include "vocal/calibration/output/camera_imu_output.h"
#include "vocal/calibration/point_statistics.h"
#include "vocal/calibration/solver/arm_pose_fit.h"
#include "vocal/calibration/solver/hand_eye_calibration.h"
#include "vocal/calibration/solver/pose_jackknife.h"
#include "vocal/calibration/solver/sensor_trust.h"
#include "vocal/core/errors.h"
#include "vocal/core/folders.h"
#include "vocal/core/se3.h"
#include "vocal/tools/bag_tool_poses.h"
#include "vocal/tools/calibration_bag.h"
#include "vocal/tools/calibration_overlays.h"
#include "vocal/tools/camera_imu_bag.h"
#include "vocal/tools/command_line.h"

namespace {
const char kUsage[] =
    "usage: calibrate_rig RIG.yaml BAG [options]\n"
    "  RIG.yaml            the rig description (sensors, topics, target, the reference sensor's pose)\n"
    "  BAG                 a recorded session: the target held still at many poses, moved in between\n"
    "  --output-dir DIR    write DIR/calibration.yaml, DIR/calibration.urdf, DIR/calibration.launch\n"
    "  --no-filter         keep every observation (no sampling-consensus filter)\n"
    "  --no-edges          hold the board's plane only (by default its outline too: range sensors' scan-line\n"
    "                      ends on its edges and the cameras' board outline, on the board's pose per still pose,\n"
    "                      which fixes a target tilted mainly up and down; --edges is accepted, the default)\n"
    "  --refine-intrinsics refine each camera's focal lengths with the poses (a 2 % prior on camera_info's;\n"
    "                      fixed by the corners' perspective and the other sensors' boards): for a camera_info\n"
    "                      whose focal length is off; printed and written to calibration.yaml\n"
    "  --report            also print, per range sensor, why messages gave no target (by the check that\n"
    "                      refused the most board-like segment), and per still pose when it was held still\n"
    "                      (bag stamps) and each sensor's residual, and each sensor's clock against the\n"
    "                      reference's (an offset beyond 0.1 s and its noise is always printed, and corrected)\n"
    "  --overlays          with --output-dir: per still pose and camera, DIR/overlay_poseNN_CAMERA.png, the\n"
    "                      camera's image with every other sensor's board points drawn where the result puts\n"
    "                      them beside the board the camera found, and how many land on it; all of them as\n"
    "                      thumbnails in DIR/overlays_contact_sheet.png\n"
    "  --tolerance-mm T    a sensor that moves more than T mm (default 10) or R mrad (default 10) when one still\n"
    "  --tolerance-mrad R  pose is left out is called uncertain, with the axis and the likely cause\n"
    "  --no-ring-offsets   take a 3D lidar's ranges as they are (by default each ring's range offset is\n"
    "                      estimated from the room's planes, floor and walls, and its board returns corrected\n"
    "                      when they predict held-out still poses better than none; beyond +-3 cm only when the\n"
    "                      room's planes also agree on them one by one, and then with a warning naming the\n"
    "                      driver's calibration)\n"
    "  --no-isolation      only name a sensor that disagrees with the others (by default it is taken out of the\n"
    "                      graph and the others solved without it, so that it moves none of them)\n"
    "  --one-graph         an arm's session solved by the still-pose graph: the board on the tool before fixed\n"
    "                      sensors (one of them given, or none: the base the rig frame), or lying still in the\n"
    "                      base under sensors on the arm; sensors on the arm's links or a head's each a frame\n"
    "                      on its chain or on the tool tf reports (trust and the jackknife as for any rig; in\n"
    "                      progress, the arm's own graph is the default)\n"
    "  --publish-uncertain also write sensors whose spread across poses is over the tolerance into the URDF and\n"
    "                      launch file (by default they are withheld and the exit status is 1)\n"
    "  --max-held-mb MB    the session's memory budget for target data (default 512; 0: none): past it, messages in\n"
    "                      no still pose are let go and each pose keeps per sensor its first 2 s, thinned to about 20\n"
    "                      messages; when full, later messages are counted, not kept\n"
    "  --threads N         messages searched for the target at once (default 0: OMP_NUM_THREADS where set, else\n"
    "                      the cores; the result is the same with any number)\n"
    "  --quiet             no progress line\n"
    "A rig whose camera has a moving frame as its `parent` (a robot arm's tool), or whose target has, is a\n"
    "hand-eye rig: the tool's pose comes from the bag's /tf and /tf_static, the arm's still poses from its\n"
    "stillness; --report adds each arm pose's fit, --tolerance-mm / --tolerance-mrad and --publish-uncertain hold.\n"
    "A sensor whose `parent` is a link of the rig's joints (a `joints:` list or a `urdf:`) is behind them (a camera\n"
    "on a pan-tilt head): the joints' positions come from the bag's sensor_msgs/JointState (joint_states_topic,\n"
    "/joint_states), its views count only where they were still, and each joint's zero offset is solved with the\n"
    "rest; --report adds the range each joint covered.\n"
    "A rig with an `imu` sensor: the IMU is calibrated against its camera from the frames where the rig was waved\n"
    "before the fixed board (every frame with the board, and the IMU's sensor_msgs/Imu): the camera's pose in the IMU\n"
    "frame and the time offset between their clocks; the IMU is placed in the rig through its camera, and\n"
    "--output-dir adds DIR/camchain-imucam.yaml (Kalibr's layout). A rig of the camera and the IMU alone needs no still\n"
    "poses.\n"
    "  --imu-bag BAG       the waved session in a recording of its own (default: BAG): the rig's other sensors from\n"
    "                      BAG's still poses, the IMU from this one, placed through its camera's result\n";

// Per sensor, its range messages without the target by the check that refused the most board-like segment.
std::vector<std::map<std::string, int>> refusedByCheck(const vocal::RigDescription& rig, const vocal::CalibrationSession& session) {
  std::vector<std::map<std::string, int>> refused(rig.sensors.size());
  for (const vocal::RangeMessage& m : session.rangeMessages())
    if (m.chosen < 0) ++refused[m.sensor][m.check];
  return refused;
}

// What a user checks a calibration by: where extraction found no board and why, and how well each
// still pose's observations fit the result.
// `refused`: refusedByCheck's.
void printReport(const vocal::RigDescription& rig, const std::vector<std::map<std::string, int>>& refused,
                 const std::vector<vocal::TargetObservation>& associated, const vocal::CalibrationResult& result, int poses) {
  std::printf("messages without the target, by the check that refused the most board-like segment:\n");
  for (std::size_t s = 0; s < rig.sensors.size(); ++s) {
    if (rig.sensors[s].spec.type == vocal::SensorType::kCamera) continue;
    std::printf("  %-12s", rig.sensors[s].spec.name.c_str());
    if (refused[s].empty()) std::printf(" none");
    for (const auto& [check, count] : refused[s]) std::printf("  %s: %d", check.c_str(), count);
    std::printf("\n");
  }
  // When each pose was held still (its sensors' runs, first to last message): where to look in the recording.
  std::vector<std::pair<double, double>> still(poses, {1e300, -1e300});
  for (const vocal::TargetObservation& o : associated) {
    still[o.target_pose].first = std::min(still[o.target_pose].first, o.first_stamp);
    still[o.target_pose].second = std::max(still[o.target_pose].second, o.last_stamp);
  }
  std::printf("residual (mm, rms point to plane) per still pose; R: rejected by the consensus filter, -: not seen\n%-6s %-21s",
              "pose", "still (s, bag stamps)");
  for (const vocal::RigSensorDescription& d : rig.sensors) std::printf(" %12s", d.spec.name.c_str());
  std::printf("\n");
  for (int pose = 0; pose < poses; ++pose) {
    char span[64];
    std::snprintf(span, sizeof(span), "%.2f-%.2f", still[pose].first, still[pose].second);
    std::printf("%-6d %-21s", pose, span);
    for (std::size_t s = 0; s < rig.sensors.size(); ++s) {
      std::string cell = "-";
      for (const vocal::ObservationResidual& o : result.observations) {
        if (o.sensor != static_cast<int>(s) || o.target_pose != pose) continue;
        char text[32] = "n/a";  // every observation of the pose rejected: no plane solved
        if (!std::isnan(o.rms)) std::snprintf(text, sizeof(text), "%.2f", 1000 * o.rms);
        cell = std::string(text) + (o.rejected ? " R" : "");
      }
      std::printf(" %12s", cell.c_str());
    }
    std::printf("\n");
  }
  // Behind joints: each still pose's readings, the range each joint covered (what the offsets are fixed by).
  const vocal::JointedMounts mounts = rig.jointedMounts();
  if (mounts.chains.empty()) return;
  std::printf("joint readings per still pose (rad; metres for a prismatic joint), as the views behind them kept them:\n");
  for (const vocal::TargetObservation& o : associated) {
    if (!mounts.jointed(o.sensor)) continue;
    std::printf("  pose %-3d %-12s", o.target_pose, rig.sensors[o.sensor].spec.name.c_str());
    for (std::size_t i = 0; i < o.joint_positions.size(); ++i)
      std::printf("  %s %+.4f", mounts.joints[mounts.chains[o.sensor][i]].name.c_str(), o.joint_positions[i]);
    std::printf("\n");
  }
}

// Per camera and other sensor, over the poses: the share of its points on the board the camera found
// and their distance to its plane (median and worst pose), so a wrong extrinsic is seen without images.
void printOverlaySummary(const vocal::RigDescription& rig, const vocal::OverlayReport& report) {
  std::printf("overlays: %zu PNGs; per camera, each sensor's board points on the board the camera found "
              "(median over poses, worst pose in brackets):\n", report.written.size());
  if (!report.contact_sheet.empty()) std::printf("  all of them as thumbnails: %s\n", report.contact_sheet.c_str());
  for (const std::string& problem : report.problems) std::printf("  not drawn: %s\n", problem.c_str());
  std::map<std::pair<int, int>, std::vector<const vocal::OverlayPoseAgreement*>> by_pair;
  for (const vocal::OverlayPoseAgreement& a : report.agreement) by_pair[{a.camera, a.sensor}].push_back(&a);
  for (auto& [pair, poses] : by_pair) {
    std::vector<double> on_board, off_plane;
    const vocal::OverlayPoseAgreement* worst = poses.front();
    for (const vocal::OverlayPoseAgreement* a : poses) {
      on_board.push_back(a->agreement.on_board);
      off_plane.push_back(a->agreement.plane_rms);
      if (a->agreement.on_board < worst->agreement.on_board) worst = a;
    }
    std::printf("  %-12s %-12s %5.1f %% on the board (pose %d: %.1f %%%s), %5.1f mm off its plane, %zu poses\n",
                rig.sensors[pair.first].spec.name.c_str(), rig.sensors[pair.second].spec.name.c_str(),
                100 * vocal::median(on_board), worst->target_pose, 100 * worst->agreement.on_board,
                worst->rejected ? ", rejected" : "",
                1000 * vocal::median(off_plane), poses.size());
  }
}

// The joints' offsets as solved, or held and why, and what their readings gave the still poses.
// A still-pose graph's joints as solved: each offset (or why held) and a free origin.
void printJointOffsets(const vocal::CalibrationResult& result) {
  std::printf("joint offsets (added to each reading), sigma, and the range the still poses covered:\n");
  for (std::size_t j = 0; j < result.joints.size(); ++j) {
    if (!result.joints[j].reported) continue;
    const vocal::JointDescription& joint = result.mounts.joints[j];
    std::printf("  %-20s %s\n", joint.name.c_str(), vocal::jointOffsetText(joint, result.joints[j], 8).c_str());
    if (result.joints[j].origin_free) std::printf("  %-20s %s\n", "", vocal::jointOriginText(result.joints[j]).c_str());
  }
}

void printJoints(const vocal::RigDescription& rig, const vocal::CalibrationSession& session, const vocal::CalibrationResult& result) {
  const vocal::JointPositionCounts counts = session.jointPositionCounts();
  std::printf("joints: %zu readings on %s; views of the sensors behind them: %d kept, %d dropped while the joints moved, %d without a "
              "reading%s%s\n",
              session.jointReadings(), rig.joint_states_topic.c_str(), counts.kept, counts.moving, counts.unread,
              counts.first.empty() ? "" : " (first: ", counts.first.empty() ? "" : (counts.first + ")").c_str());
  printJointOffsets(result);
}

// The spread between still poses (the jackknife) beside the solver's sigma, and where it is far larger:
// the solver takes every point's error as independent, the spread sees errors a pose's points share.
void printJackknife(const std::vector<vocal::SensorSpec>& specs, int reference, const vocal::PoseJackknife& jackknife,
                    const vocal::CalibrationResult& result) {
  std::printf("spread across still poses (jackknife: %d of %d re-solves, each without one pose), beside the solver's sigma:\n",
              jackknife.solved, jackknife.poses);
  for (std::size_t s = 0; s < specs.size(); ++s) {
    if (static_cast<int>(s) == reference) continue;
    const double t = jackknife.standard_deviation[s].head<3>().norm(), r = jackknife.standard_deviation[s].tail<3>().norm();
    const double solver_t = result.sensors[s].standard_deviation.head<3>().norm();
    const double solver_r = result.sensors[s].standard_deviation.tail<3>().norm();
    std::printf("  %-12s %6.2f mm (solver %.2f), %6.2f mrad (solver %.2f)", specs[s].name.c_str(), 1000 * t,
                1000 * solver_t, 1000 * r, 1000 * solver_r);
    const double ratio = std::max(t / std::max(solver_t, 1e-9), r / std::max(solver_r, 1e-9));
    if (ratio > 3.0) std::printf("  %.0fx the solver's: errors its points share within a pose (ring biases, hands, lens model)", ratio);
    std::printf("\n");
  }
}

// Each 3D lidar's ring offsets and whether its board returns were corrected by them, and why: a ring far
// off, or a sigma near the prior's, says what the room gave.
void printRingOffsets(const vocal::RigDescription& rig, const std::vector<std::optional<vocal::RingOffsets>>& offsets) {
  for (std::size_t s = 0; s < rig.sensors.size(); ++s) {
    const std::optional<vocal::RingOffsets>& rings = offsets[s];
    if (!rings) continue;
    if (rings->elevations.empty()) {
      std::printf("%s: ring offsets %s\n", rig.sensors[s].spec.name.c_str(), rings->verdict.c_str());
      continue;
    }
    std::printf("%s: range offset per ring (mm, by elevation; from %d room planes, %zu returns, %.1f mm rms off them once corrected, "
                "%.1f mm as measured; %d planes seen only at grazing incidence left out):\n",
                rig.sensors[s].spec.name.c_str(), rings->planes, rings->returns, 1000 * rings->rms, 1000 * rings->rms_as_measured,
                rings->grazing_planes);
    for (std::size_t r = 0; r < rings->elevations.size(); ++r) {
      std::printf("  %+6.1f deg %+6.1f +- %.1f%s", rings->elevations[r] * 180.0 / M_PI, 1000 * rings->offsets[r], 1000 * rings->sigmas[r],
                  r % 4 == 3 || r + 1 == rings->elevations.size() ? "\n" : "");
    }
    std::printf("  one offset for all rings, plane by plane: %+.1f mm (median), %.0f %% of the planes' say within +-%.0f mm of it\n",
                1000 * rings->common_offset, 100 * rings->planes_agreeing, 1000 * rings->agreement);
    std::printf("  ring offsets %s\n", rings->verdict.c_str());
    if (!rings->warning.empty()) std::printf("warning: %s: %s\n", rig.sensors[s].spec.name.c_str(), rings->warning.c_str());
  }
}

// A rig whose joints came from the robot's URDF: that URDF with the joints' offsets solved, beside the result.
void writeRobotUrdf(const vocal::RigDescription& rig, const std::map<std::string, double>& offsets, const std::string& dir,
                    const std::map<std::string, Eigen::Isometry3d>& origins = {}) {
  if (rig.urdf_path.empty() || (offsets.empty() && origins.empty())) return;
  vocal::writeCalibratedUrdf(rig.urdf_path, dir + "/robot_calibrated.urdf", offsets, origins);
  std::printf("wrote %s/robot_calibrated.urdf: %s with the %zu solved joint offsets as <calibration rising=...>", dir.c_str(), rig.urdf.c_str(),
              offsets.size());
  if (!origins.empty()) std::printf(" and the %zu free origins as solved", origins.size());
  std::printf("\n");
}

double positiveOption(const vocal::CommandLine& args, const char* name, double fallback) {
  const double value = args.number(name, fallback);
  if (!(value > 0.0)) throw vocal::InputError(std::string("option --") + name + ": must be > 0 (got " + args.text(name, "") + ")");
  return value;
}

void printPose(const char* what, const Eigen::Isometry3d& pose, const Eigen::Matrix<double, 6, 1>* sigma, const Eigen::Matrix<double, 6, 1>* spread) {
  const Eigen::Vector3d t = pose.translation();
  const Eigen::Quaterniond q(pose.rotation());
  std::printf("%-28s %10.5f %10.5f %10.5f %10.6f %10.6f %10.6f %10.6f", what, t.x(), t.y(), t.z(), q.x(), q.y(), q.z(), q.w());
  if (sigma) std::printf("   %.2f / %.2f", 1000 * sigma->head<3>().norm(), 1000 * sigma->tail<3>().norm());
  if (spread) std::printf(", %.2f / %.2f", 1000 * spread->head<3>().norm(), 1000 * spread->tail<3>().norm());
  std::printf("\n");
}

// A camera's intrinsics refined with the poses (--refine-intrinsics), and what to do when they moved far.
// A 2D laser's beam radius as its scan ends put it (metres at its exit, radians times the range).
void printBeamRadius(const std::string& name, const Eigen::Vector2d& beam) {
  std::printf("%s's beam as its scan ends reach past the board's edges: radius %.1f mm + %.1f mrad x range (%.1f mm at 1 m)\n",
              name.c_str(), 1000 * beam[0], 1000 * beam[1], 1000 * (beam[0] + beam[1]));
}

void printRefinedIntrinsics(const std::string& name, const Eigen::Vector4d& given, const Eigen::Vector4d& refined, const Eigen::Vector4d& sigma) {
  const double change = 100.0 * (refined[0] / given[0] - 1.0);
  std::printf("intrinsics: %s: focal lengths fx %.1f -> %.1f, fy %.1f -> %.1f px (%+.1f %%, sigma %.1f px)", name.c_str(), given[0], refined[0],
              given[1], refined[1], change, sigma[0]);
  if (refined.tail<2>() != given.tail<2>()) std::printf(", principal point (%.1f, %.1f) -> (%.1f, %.1f) px", given[2], given[3], refined[2], refined[3]);
  std::printf("%s\n", std::abs(change) > 1.0 ? ": its camera_info is off by more than 1 %; put the refined values in its K" : "");
}

// Every IMU of the rig against its camera from the waved frames, placed in the rig through its camera:
// `camera_pose` gives a sensor's pose in its parent frame (left empty: the rig's reference frame; an arm's tool
// or link for a camera the arm moves), or none with why (withheld, not placed).
using CameraPlacement = std::function<std::optional<Eigen::Isometry3d>(int, std::string* why, std::string* parent)>;

std::vector<vocal::ImuCalibrationOutput> calibrateImus(const vocal::CommandLine& args, const vocal::RigDescription& rig, const std::string& bag,
                                                       const CameraPlacement& camera_pose) {
  std::vector<vocal::ImuCalibrationOutput> outputs;
  for (std::size_t i = 0; i < rig.imus.size(); ++i) {
    const vocal::RigImuDescription& imu = rig.imus[i];
    const vocal::RigSensorDescription& camera = rig.sensors[imu.camera];
    vocal::ImuCalibrationOutput out;
    out.name = imu.name;
    out.frame_id = imu.frame_id;
    out.camera_name = camera.spec.name;
    out.camera_frame = camera.spec.frame_id;
    out.camera_topic = camera.image_topic;
    // The waved frames: in the session's recording, or in one of their own (--imu-bag).
    const vocal::CameraImuRecording recording =
        vocal::readCameraImuBag(args.text("imu-bag", bag), rig, static_cast<int>(i), args.integer("threads", 0));
    out.camera = recording.camera;
    out.lens = recording.lens;
    const double rate = vocal::imuRate(recording.imu);
    std::printf("imu '%s' against camera '%s': the board in %zu of %zu frames, %zu IMU samples (%.1f Hz), %zu messages dropped\n", imu.name.c_str(),
                camera.spec.name.c_str(), recording.views.size(), recording.images, recording.imu.size(), rate, recording.dropped);
    for (const std::string& problem : recording.problems) std::printf("  dropped: %s\n", problem.c_str());
    try {
      // Each frame's corners through the camera's lens (its camera_info's model) in the graph.
      vocal::CameraImuOptions options;
      options.camera_model = vocal::CameraImuCameraModel{recording.camera, recording.lens, rig.target.pattern};
      out.result = vocal::calibrateCameraImu(recording.views, recording.imu, imu.noise, options);
    } catch (const vocal::InputError& e) {
      out.withheld = std::string("not calibrated: ") + e.what();
      std::printf("withheld: imu '%s' %s\n", imu.name.c_str(), out.withheld.c_str());
      outputs.push_back(out);
      continue;
    }
    const vocal::CameraImuResult& r = out.result;
    std::printf("  closed forms: time offset %+.2f ms (the angular speeds correlate %.3f there), rotation from the angular velocities\n",
                1000 * r.initial_time_offset, r.angular_speed_correlation);
    if (r.views_at_rest > 0) {
      std::printf("  %d view%s outside the span where the gyro turns (the rig at rest): not used\n", r.views_at_rest,
                  r.views_at_rest == 1 ? "" : "s");
    }
    if (r.left_out_views > 0) {
      std::printf("  %d view%s left out: the board turned away and straight back between its neighbours (PnP's mirrored solution of "
                  "a board seen small or square on)\n", r.left_out_views, r.left_out_views == 1 ? "" : "s");
    }
    printPose((camera.spec.name + " in " + imu.name).c_str(), r.camera_in_imu, &r.sigma, nullptr);
    std::printf("  time offset: IMU stamp = camera stamp %+.3f ms (sigma %.3f ms)\n", 1000 * r.time_offset, 1000 * r.time_offset_sigma);
    std::printf("  biases: gyro [%.5f, %.5f, %.5f] rad/s, accelerometer [%.4f, %.4f, %.4f] m/s^2\n", r.gyro_bias.x(), r.gyro_bias.y(),
                r.gyro_bias.z(), r.accel_bias.x(), r.accel_bias.y(), r.accel_bias.z());
    std::printf("  residuals (rms): gyro %.4f rad/s, accelerometer %.4f m/s^2 (its noise figures say %.4f / %.4f), board views %.2f mm / "
                "%.2f mrad; %d views, %d IMU samples, %d iterations\n",
                r.gyro_rms, r.accel_rms, imu.noise.gyro_noise_density * std::sqrt(rate), imu.noise.accel_noise_density * std::sqrt(rate),
                1000 * r.view_translation_rms, 1000 * r.view_rotation_rms, r.views, r.imu_samples, r.iterations);
    out.withheld = r.withheld;
    if (rig.reference_imu == static_cast<int>(i)) {
      out.rig_from_imu = *imu.pose;
    } else {
      std::string why;
      if (const std::optional<Eigen::Isometry3d> placed = camera_pose(imu.camera, &why, &out.parent_frame)) {
        out.rig_from_imu = *placed * r.camera_in_imu.inverse();
      } else if (out.withheld.empty()) {
        out.withheld = "its camera '" + camera.spec.name + "' is not placed in the rig (" + why + ")";
      }
    }
    const std::string parent = out.parent_frame.empty() ? rig.reference_frame : out.parent_frame;
    if (out.rig_from_imu) printPose((imu.name + " in " + parent).c_str(), *out.rig_from_imu, nullptr, nullptr);
    if (!out.withheld.empty()) {
      std::printf("withheld: imu '%s' is kept out of calibration.urdf and calibration.launch: %s\n", imu.name.c_str(), out.withheld.c_str());
    }
    outputs.push_back(out);
  }
  return outputs;
}

// The IMUs' results beside the rig's files: their block of calibration.yaml, their joints and transforms in
// the URDF snippet and launch file, and Kalibr's camchain-imucam.yaml.
void writeImuOutputs(const std::string& dir, const vocal::RigDescription& rig, const std::vector<vocal::ImuCalibrationOutput>& imus) {
  const auto append = [](const std::string& path, const std::string& text, const std::string& before) {
    std::ifstream in(path);
    std::string content((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    const std::size_t at = before.empty() ? std::string::npos : content.rfind(before);
    content.insert(at == std::string::npos ? content.size() : at, text);
    std::ofstream out(path);
    if (!(out << content) || !out.flush()) throw vocal::InputError(path + ": cannot write calibration output");
  };
  append(dir + "/calibration.yaml", vocal::imuCalibrationYaml(imus, rig.reference_frame), "");
  append(dir + "/calibration.urdf", vocal::imuUrdfJoints(imus, rig.reference_frame), "");
  append(dir + "/calibration.launch", vocal::imuStaticTransformNodes(imus, rig.reference_frame), "</launch>");
  vocal::writeKalibrCamchain(dir + "/camchain-imucam.yaml", imus);
  std::printf("wrote %s/camchain-imucam.yaml (Kalibr's layout) and the IMUs into calibration.yaml, calibration.urdf, calibration.launch\n",
              dir.c_str());
}

// A camera on an arm's tool, or the board in its gripper: the arm's still poses from the recording's tf.
// The end of a run with still poses: the rig's IMUs calibrated through their cameras (placed by `place`),
// or the ones `calibrated` first (a reference IMU's rig), and their outputs written. Whether any is
// withheld.
bool finishImus(const vocal::CommandLine& args, const vocal::RigDescription& rig, const std::string& bag, const CameraPlacement& place,
                const std::vector<vocal::ImuCalibrationOutput>* calibrated = nullptr) {
  if (rig.imus.empty()) return false;
  const std::vector<vocal::ImuCalibrationOutput> imus = calibrated ? *calibrated : calibrateImus(args, rig, bag, place);
  bool withheld = false;
  for (const vocal::ImuCalibrationOutput& imu : imus) withheld = withheld || !imu.withheld.empty();
  if (args.has("output-dir")) writeImuOutputs(args.text("output-dir", ""), rig, imus);
  return withheld;
}

// After a still-pose graph's solve: the spread across still poses (the jackknife re-solving `observations`
// with `options`) beside the solver's sigma and the sensors over `tolerance`, the observability warnings,
// and what is not trusted. The spread, or none where too few re-solves succeeded.
std::optional<vocal::PoseJackknife> printSpreadAndVerdicts(const std::vector<vocal::SensorSpec>& specs, int reference,
                                                           const std::vector<vocal::TargetObservation>& observations,
                                                           const vocal::CalibrationOptions& options, const vocal::CalibrationResult& result,
                                                           const vocal::SpreadTolerance& tolerance) {
  std::optional<vocal::PoseJackknife> spread;
  try {
    spread = vocal::jackknifeOverPoses(specs, observations, options, result);
    printJackknife(specs, reference, *spread, result);
    for (const std::string& line : vocal::spreadOverTolerance(*spread, specs, tolerance)) std::printf("uncertain: %s\n", line.c_str());
  } catch (const vocal::InputError& e) {
    std::printf("spread across still poses: not computed (%s)\n", e.what());
  }
  for (const vocal::ObservabilityWarning& w : result.warnings) std::printf("warning: %s\n", w.message.c_str());
  if (!result.trusted) std::printf("NOT TRUSTED: %s\n", result.failure.c_str());
  for (std::size_t s = 0; s < specs.size(); ++s) {
    if (!result.sensors[s].distrust.empty()) std::printf("NOT TRUSTED: sensor '%s': %s\n", specs[s].name.c_str(), result.sensors[s].distrust.c_str());
  }
  return spread;
}

// The sensors withheld from the URDF and launch file (printed with why; per sensor in the result, "" for
// those published) and, with --output-dir, the result YAML, URDF snippet, launch file and the robot's URDF
// with the joints as solved.
std::vector<std::string> withholdAndWrite(const vocal::CommandLine& args, const vocal::RigDescription& rig, const std::vector<vocal::SensorSpec>& specs,
                                          int reference, const vocal::CalibrationResult& result, const std::optional<vocal::PoseJackknife>& spread,
                                          const std::vector<std::optional<vocal::RingOffsets>>* ring_offsets, const vocal::SpreadTolerance& tolerance) {
  const std::vector<std::string> withheld =
      vocal::withheldSensors(specs, reference, result, spread ? &*spread : nullptr, tolerance, args.has("publish-uncertain"));
  bool any_withheld = false;
  for (std::size_t s = 0; s < specs.size(); ++s) {
    if (withheld[s].empty()) continue;
    std::printf("withheld: sensor '%s' is kept out of calibration.urdf and calibration.launch: %s\n", specs[s].name.c_str(), withheld[s].c_str());
    any_withheld = true;
  }
  if (any_withheld && result.trusted) {
    std::printf("  its values are in calibration.yaml; calibrate again as the NOT TRUSTED or uncertain line says, or pass --publish-uncertain to "
                "publish them anyway\n");
  }
  if (!args.has("output-dir")) return withheld;
  const std::string dir = args.text("output-dir", "");
  vocal::writeCalibrationYaml(dir + "/calibration.yaml", rig.reference_frame, specs, result, spread ? &*spread : nullptr, ring_offsets, &withheld);
  vocal::writeUrdfSnippet(dir + "/calibration.urdf", rig.reference_frame, specs, result, &withheld);
  vocal::writeStaticTransformLaunch(dir + "/calibration.launch", rig.reference_frame, specs, result, &withheld);
  std::printf("wrote %s/calibration.yaml, calibration.urdf, calibration.launch\n", dir.c_str());
  std::map<std::string, double> offsets;
  std::map<std::string, Eigen::Isometry3d> origins;
  for (std::size_t j = 0; j < result.joints.size() && j < result.mounts.joints.size(); ++j) {
    if (result.joints[j].held.empty()) offsets[result.mounts.joints[j].name] = result.joints[j].offset;
    if (result.joints[j].origin_free) origins[result.mounts.joints[j].name] = result.joints[j].origin;
  }
  writeRobotUrdf(rig, offsets, dir, origins);
  return withheld;
}

// The one graph's arm poses: OpenCV's closed forms beside the result for the first camera they apply to,
// each poor pose named with where to look in the recording, and with --report every pose's fit; numbered
// from 0 as the still-pose graph's other outputs (trust, overlays) number them.
void printArmPoseFits(const vocal::CommandLine& args, const vocal::HandEyeAssociation& association, const std::vector<vocal::SensorSpec>& specs,
                      const std::vector<vocal::TargetObservation>& observations, const vocal::CalibrationResult& result) {
  const std::map<int, vocal::ArmPoseFit> fits = vocal::armPoseFits(specs, observations, result);
  for (const auto& [k, fit] : fits) {
    if (!fit.poor) continue;
    std::printf("poor still pose %d (%.1f-%.1f s): to fit the others what the arm holds had to move %.2f mm / %.2f mrad from where the arm "
                "put it, %.0f sigma of its repeatability (the arm's pose, or the camera's view of the board there, is off); it does not "
                "pull the result\n", k, association.stations[k].first_stamp, association.stations[k].last_stamp, 1000 * fit.shift,
                1000 * fit.turn, fit.departure);
  }
  for (std::size_t s = 0; s < specs.size(); ++s) {
    const int camera = static_cast<int>(s);
    if (specs[s].type != vocal::SensorType::kCamera || result.sensors[s].isolated || !vocal::handEyeClosedFormApplies(result.mounts, camera))
      continue;
    const vocal::HandEyeViews seen = vocal::handEyeViews(result.mounts, observations, camera);
    if (seen.frames.size() < 3) continue;
    const Eigen::Isometry3d& solved = result.sensors[s].reference_from_sensor;
    std::printf("OpenCV's calibrateHandEye on the same poses, for %s, against this result:\n", specs[s].name.c_str());
    for (const vocal::HandEyeClosedForm& c : vocal::openCvHandEyeMethods(seen.frames, seen.views)) {
      std::printf("  %-10s %6.2f mm / %.3f deg\n", c.method.c_str(), 1000 * (c.camera.translation() - solved.translation()).norm(),
                  vocal::rotationAngle(solved.inverse() * c.camera) * 180 / M_PI);
    }
    break;
  }
  if (!args.has("report")) return;
  std::printf("arm poses (bag stamps), how far the solve moved what the arm holds, and the camera views against the solution:\n");
  for (const auto& [k, fit] : fits) {
    std::printf("  pose %2d  %.2f-%.2f s  %zu views  moved %.3f mm / %.3f mrad (%.1f sigma)  board off %.2f mm / %.2f mrad%s\n", k,
                association.stations[k].first_stamp, association.stations[k].last_stamp, association.stations[k].views.size(),
                1000 * fit.shift, 1000 * fit.turn, fit.departure, 1000 * fit.view_distance, 1000 * fit.view_angle, fit.poor ? "  poor" : "");
  }
}

// --one-graph (issue 44, in progress): an arm holding the board before fixed sensors, one of them given (the
// reference) or none (the base the rig frame), or moving sensors over a board lying still in its base
// (eye-in-hand; the base the rig frame), solved by the still-pose graph: the board a frame on the tool (from
// the joints or tf) or in the base, the sensors on the arm's links or a head's each a frame on its chain (or
// on the tool tf reports): trust, the jackknife and the still-pose outputs as for any rig.
int runArmInOneGraph(const vocal::CommandLine& args, const vocal::RigDescription& rig, const std::string& bag, const vocal::HandEyeRig& arm,
                     const vocal::HandEyeFrames& frames, const vocal::HandEyeAssociation& association, const vocal::HandEyeOptions& arm_options,
                     const vocal::SpreadTolerance& tolerance) {
  int reference = -1;
  for (std::size_t s = 0; s < frames.sensors.size(); ++s) {
    if (reference < 0 && !frames.on_tool[s] && frames.given_poses[s]) reference = static_cast<int>(s);
  }
  // (The board's size is always there: readRigDescription requires it, or for a rig of cameras alone takes
  // the pattern's extent.)
  if (arm.eye_in_hand) {
    for (std::size_t s = 0; s < frames.sensors.size(); ++s) {
      if (!frames.on_tool[s]) {
        throw vocal::InputError("option --one-graph: sensor '" + frames.sensors[s].name + "' stands fixed beside a board that stands fixed too, "
                                "so no still pose tells it anything: calibrate it in a session with the board on the arm or by hand");
      }
    }
  }
  const std::vector<vocal::SensorSpec> specs = frames.sensors;
  vocal::CalibrationOptions options;
  // No fixed sensor's pose given (or the board lying still): the arm's base is the rig frame.
  options.reference_sensor = arm.eye_in_hand ? -1 : reference;
  if (options.reference_sensor >= 0) options.reference_pose = *frames.given_poses[reference];
  options.board_edges.enabled = true;
  options.board_edges.width = rig.target.width, options.board_edges.height = rig.target.height;
  // Each camera view as its whole PnP pose, as the arm's graph takes it: with the board on the tool its
  // place within its plane is the arm's, and the camera's own fixes it far better than its outline.
  options.board_edges.camera_pose = true;
  options.intrinsics = arm_options.intrinsics;
  options.trust.isolate = !args.has("no-isolation");
  vocal::JointedMounts& mounts = options.mounts;
  mounts.tool_translation_sigma = arm_options.tool_translation_sigma, mounts.tool_rotation_sigma = arm_options.tool_rotation_sigma;
  mounts.tool_loss_sigmas = arm_options.loss_sigmas;
  mounts.board_fixed = arm.eye_in_hand;
  if (arm_options.arm_joints) {
    mounts.joints = arm_options.arm_joints->joints;
    mounts.tolerances = arm_options.arm_joints->tolerances;
    if (!arm.eye_in_hand) mounts.board_chain = arm_options.arm_joints->chain;
    // A sensor on the tool moves with the tool's chain; one on another link (a forearm, a head) with its own.
    mounts.chains.assign(specs.size(), {});
    mounts.known_mounts.assign(specs.size(), std::nullopt);
    for (std::size_t s = 0; s < specs.size(); ++s) {
      if (!frames.on_tool[s]) continue;
      mounts.chains[s] = frames.link_chains[s].empty() ? arm_options.arm_joints->chain : frames.link_chains[s];
      mounts.known_mounts[s] = frames.given_poses[s];
    }
  } else {
    // Sensors on the tool at the poses tf reported for it.
    mounts.on_reported_tool = frames.on_tool;
    mounts.known_mounts.assign(specs.size(), std::nullopt);
    for (std::size_t s = 0; s < specs.size(); ++s)
      if (frames.on_tool[s]) mounts.known_mounts[s] = frames.given_poses[s];
  }
  mounts.tool_frame = arm.tool_frame;  // the frame sensors on the reported tool are in, and the board on it
  for (std::size_t k = 0; k < association.stations.size(); ++k) {
    const vocal::HandEyeStation& station = association.stations[k];
    if (arm_options.arm_joints) {
      if (!arm.eye_in_hand)
        mounts.board_readings[static_cast<int>(k)] = vocal::chainReadings(arm_options.arm_joints->readJoints(), station.joint_positions, mounts.board_chain);
    } else {
      mounts.tool_poses[static_cast<int>(k)] = station.base_from_tool;
      if (!arm.eye_in_hand) mounts.board_tool_poses[static_cast<int>(k)] = station.base_from_tool;
    }
  }
  std::vector<vocal::TargetObservation> observations = vocal::stillPoseObservations(association.stations, rig.target.pattern);
  if (arm_options.arm_joints) {
    for (vocal::TargetObservation& o : observations)
      if (mounts.jointed(o.sensor))
        o.joint_positions = vocal::chainReadings(arm_options.arm_joints->readJoints(), association.stations.at(o.target_pose).joint_positions,
                                                 mounts.chains[o.sensor]);
  }
  const vocal::CalibrationResult result = vocal::calibrateRigWithTrust(specs, observations, options);
  if (arm.eye_in_hand) {
    std::printf("one graph: the board lying still in %s (the rig frame), the sensors on %s (%s), %zu still poses\n", rig.reference_frame.c_str(),
                arm.tool_frame.c_str(), arm_options.arm_joints ? "from the arm's joints" : "from tf", association.stations.size());
  } else {
    std::printf("one graph: the board a frame on %s (%s), %zu still poses%s\n", arm.tool_frame.c_str(),
                arm_options.arm_joints ? "from the arm's joints" : "from tf", association.stations.size(),
                reference < 0 ? (", no sensor's pose given: " + rig.reference_frame + ", the arm's base, is the rig frame").c_str() : "");
  }
  if (arm_options.arm_joints) printJointOffsets(result);
  std::printf("%-12s %10s %10s %10s %10s %10s %10s %10s   %s\n", "sensor", "x", "y", "z", "qx", "qy", "qz", "qw", "sigma t (mm) / r (mrad)");
  const auto printPoseRow = [](const std::string& name, const Eigen::Isometry3d& pose, const vocal::Vector6d& sigma, const char* note) {
    const Eigen::Vector3d t = pose.translation();
    const Eigen::Quaterniond q(pose.rotation());
    std::printf("%-12s %10.5f %10.5f %10.5f %10.6f %10.6f %10.6f %10.6f   %.2f / %.2f%s\n", name.c_str(), t.x(), t.y(), t.z(), q.x(), q.y(),
                q.z(), q.w(), 1000 * sigma.head<3>().norm(), 1000 * sigma.tail<3>().norm(), note);
  };
  for (std::size_t s = 0; s < specs.size(); ++s) {
    const std::string parent = vocal::sensorParent(result, s, rig.reference_frame);
    const std::string note = static_cast<int>(s) == reference ? " (held at the pose the rig gives)"
                             : result.sensors[s].isolated     ? " (isolated)"
                             : parent != rig.reference_frame  ? " (in " + parent + ")"
                                                              : "";
    printPoseRow(specs[s].name, result.sensors[s].reference_from_sensor, result.sensors[s].standard_deviation, note.c_str());
  }
  if (result.board_mount) {
    printPoseRow("board", *result.board_mount, result.board_mount_sigma,
                 (" (in " + (arm.eye_in_hand ? rig.reference_frame : arm.tool_frame) + ")").c_str());
  }
  std::printf("the print on the board: %+.1f / %+.1f mm from its centre along its x / y, turned %+.1f mrad (where range sensors see the "
              "board's edges; else held at the centre)\n", 1000 * result.print_on_board.x(), 1000 * result.print_on_board.y(),
              1000 * result.print_on_board.z());
  if (result.view_scatter && result.view_scatter->translation > 0.0) {
    std::printf("the camera views disagree beyond the corners' noise and the arm's repeatability by %.2f mm / %.2f mrad per axis (the arm's "
                "kinematics, the camera's intrinsics, the print): each view weighted by it\n", 1000 * result.view_scatter->translation,
                1000 * result.view_scatter->rotation);
  }
  if (result.misdetected_views > 0) {
    std::printf("%d camera view%s held by %s plane only: the board over %.0f mm / %.0f mrad from where the started rig put it "
                "(a pattern found shifted by a square, or something else seen)\n", result.misdetected_views,
                result.misdetected_views == 1 ? "" : "s", result.misdetected_views == 1 ? "its" : "their", 1000 * vocal::kMisdetectedViewDistance,
                1000 * vocal::kMisdetectedViewAngle);
  }
  printArmPoseFits(args, association, specs, observations, result);
  const std::optional<vocal::PoseJackknife> spread =
      printSpreadAndVerdicts(specs, reference, observations, vocal::withIsolatedSensors(options, result), result, tolerance);
  const std::vector<std::string> withheld = withholdAndWrite(args, rig, specs, reference, result, spread, nullptr, tolerance);
  const bool any_withheld = std::any_of(withheld.begin(), withheld.end(), [](const std::string& why) { return !why.empty(); });
  if (args.has("output-dir") && args.has("overlays"))
    printOverlaySummary(rig, vocal::writeCalibrationOverlays(bag, rig, observations, result, args.text("output-dir", "")));
  // The IMUs through their cameras, in the frame each camera is mounted in (its link, or the tool).
  const bool imu_withheld = finishImus(args, rig, bag, [&](int s, std::string* why, std::string* parent) {
    *why = withheld[s].empty() ? std::string() : "withheld: " + withheld[s];
    *parent = vocal::sensorParent(result, s, rig.reference_frame);
    return withheld[s].empty() ? std::optional<Eigen::Isometry3d>(result.sensors[s].reference_from_sensor) : std::nullopt;
  });
  return any_withheld || imu_withheld ? 1 : 0;
}

int runHandEye(const vocal::CommandLine& args, const vocal::RigDescription& rig, const vocal::HandEyeRig& arm, vocal::CalibrationSession& session,
               const std::string& bag, const vocal::SpreadTolerance& tolerance) {
  vocal::HandEyeOptions options = session.handEyeOptions();
  options.intrinsics.enabled = args.has("refine-intrinsics");
  if (arm.from_joints) {
    // The tool from the arm's joint states (read with the session), its joints' offsets solved.
    std::printf("%zu joint readings on %s: the tool %s from the arm's %zu joints\n", session.jointReadings(), rig.joint_states_topic.c_str(),
                arm.tool_frame.c_str(), arm.chain.size());
    if (session.jointReadings() == 0) {
      throw vocal::InputError(bag + ": the arm's tool '" + arm.tool_frame + "' comes from its joints, but the bag has no sensor_msgs/JointState on " +
                              rig.joint_states_topic + " naming them");
    }
  } else {
    const vocal::BagToolPoses tool = vocal::readToolPosesFromBag(bag, rig.reference_frame, arm.tool_frame, &session);
    std::printf("%zu poses of %s in %s from the recording's tf", tool.samples, arm.tool_frame.c_str(), rig.reference_frame.c_str());
    if (tool.failed_lookups > 0) std::printf(", %zu lookups failed (last: %s)", tool.failed_lookups, tool.last_failure.c_str());
    std::printf("\n");
  }
  const vocal::HandEyeAssociation association = session.handEyeAssociation();
  std::printf("%zu still poses of the arm with the board in view (of %d still; %d views while the arm moved, %d where tf gave no "
              "tool pose)\n",
              association.stations.size(), association.still_spans, association.views_in_motion, association.views_without_tool);
  const vocal::HandEyeFrames frames = vocal::handEyeFrames(rig, arm);
  if (args.has("one-graph")) return runArmInOneGraph(args, rig, bag, arm, frames, association, options, tolerance);
  const vocal::HandEyeResult result = vocal::calibrateArmRig(frames.solverSensors(), !arm.eye_in_hand, association.stations, options);
  if (options.arm_joints) {
    std::printf("joint offsets (added to each reading), sigma, and the range the arm's still poses covered:\n");
    for (std::size_t i = 0; i < result.joints.size(); ++i) {
      if (!result.joints[i].reported) continue;
      const vocal::JointDescription& joint = options.arm_joints->joints[options.arm_joints->readJoints()[i]];
      std::printf("  %-20s %s\n", joint.name.c_str(), vocal::jointOffsetText(joint, result.joints[i], 8).c_str());
      if (result.joints[i].origin_free) std::printf("  %-20s %s\n", "", vocal::jointOriginText(result.joints[i]).c_str());
    }
  }
  const std::string board_parent = arm.eye_in_hand ? rig.reference_frame : arm.tool_frame;
  std::printf("%-28s %10s %10s %10s %10s %10s %10s %10s   sigma t (mm) / r (mrad), spread across the arm's poses\n",
              vocal::handEyeSetupName(result.setup).c_str(), "x", "y", "z", "qx", "qy", "qz", "qw");
  for (std::size_t s = 0; s < rig.sensors.size(); ++s) {
    printPose((rig.sensors[s].spec.name + " in " + frames.parentOf(s)).c_str(), result.sensors[s], &result.sensor_sigmas[s],
              &result.sensor_spreads[s]);
  }
  printPose(("board in " + board_parent).c_str(), result.board, &result.board_sigma, nullptr);
  for (std::size_t s = 0; s < rig.sensors.size(); ++s) {
    if (!result.given_intrinsics[s].isZero())
      printRefinedIntrinsics(rig.sensors[s].spec.name, result.given_intrinsics[s], result.refined_intrinsics[s], result.intrinsics_sigma[s]);
  }
  for (std::size_t s = 0; s < rig.sensors.size(); ++s) {
    if (result.held[s]) std::printf("%s held at the pose the rig gives in %s\n", rig.sensors[s].spec.name.c_str(), frames.parentOf(s).c_str());
  }
  for (std::size_t s = 0; s < rig.sensors.size(); ++s)
    if (result.beam_solved[s]) printBeamRadius(rig.sensors[s].spec.name, result.beam_radius[s]);
  std::printf("spread across the arm's poses: %d re-solves, each without one pose\n", result.spread_solves);
  std::printf("each camera view of the board against the solution: %.2f mm / %.2f mrad rms\n", 1000 * result.rms_distance, 1000 * result.rms_angle);
  if (result.misdetected_views > 0) {
    std::printf("  %d camera view%s left out: the board over %.0f mm / %.0f mrad from where the other views put it (a pattern found "
                "shifted by a square, or something else seen)\n", result.misdetected_views, result.misdetected_views == 1 ? "" : "s",
                1000 * vocal::kMisdetectedViewDistance, 1000 * vocal::kMisdetectedViewAngle);
  }
  if (result.unmodelled_translation > 0.0) {
    std::printf("  beyond the corners' noise and the arm's repeatability by %.2f mm / %.2f mrad per axis (the arm's kinematics, the "
                "camera's intrinsics, the print): each view weighted by it\n",
                1000 * result.unmodelled_translation, 1000 * result.unmodelled_rotation);
  }
  for (const int k : result.poor_stations) {
    std::printf("poor arm pose %d (%.1f-%.1f s): to fit the others the tool had to move %.2f mm / %.2f mrad from where the arm reported it "
                "(the arm's pose, or the camera's view of the board there, is off); it does not pull the result\n",
                k + 1, association.stations[k].first_stamp, association.stations[k].last_stamp, 1000 * result.tool_shift[k],
                1000 * result.tool_turn[k]);
  }
  std::printf("OpenCV's calibrateHandEye on the same poses, for %s, against this result:\n", rig.sensors[result.main_camera].spec.name.c_str());
  for (const vocal::HandEyeClosedForm& c : result.closed_forms) {
    std::printf("  %-10s %6.2f mm / %.3f deg\n", c.method.c_str(), 1000 * (c.camera.translation() - result.camera().translation()).norm(),
                vocal::rotationAngle(result.camera().inverse() * c.camera) * 180 / M_PI);
  }
  if (args.has("report")) {
    std::printf("arm poses (bag stamps), how far the solve moved the tool, and the board against the solution:\n");
    for (std::size_t k = 0; k < association.stations.size(); ++k) {
      std::printf("  pose %2zu  %.2f-%.2f s  %zu views  tool moved %.3f mm / %.3f mrad  board off %.2f mm / %.2f mrad\n", k + 1,
                  association.stations[k].first_stamp, association.stations[k].last_stamp, association.stations[k].views.size(),
                  1000 * result.tool_shift[k], 1000 * result.tool_turn[k], 1000 * result.view_distance[k], 1000 * result.view_angle[k]);
    }
  }
  std::vector<std::string> withheld;
  bool any_withheld = false;
  for (std::size_t s = 0; s < rig.sensors.size(); ++s) {
    withheld.push_back(vocal::handEyeWithheld(result, s, rig.sensors[s].spec.type, tolerance, args.has("publish-uncertain")));
    if (withheld.back().empty()) continue;
    std::printf("withheld: sensor '%s' is kept out of calibration.urdf and calibration.launch: %s\n", rig.sensors[s].spec.name.c_str(),
                withheld.back().c_str());
    any_withheld = true;
  }
  if (any_withheld) std::printf("  its values are in calibration.yaml; pass --publish-uncertain to publish them anyway\n");
  if (args.has("output-dir")) {
    const std::string dir = args.text("output-dir", "");
    vocal::writeHandEyeYaml(dir + "/calibration.yaml", frames, result, withheld);
    vocal::writeHandEyeUrdf(dir + "/calibration.urdf", frames, result, withheld);
    vocal::writeHandEyeLaunch(dir + "/calibration.launch", frames, result, withheld);
    std::printf("wrote %s/calibration.yaml, calibration.urdf, calibration.launch\n", dir.c_str());
    std::map<std::string, double> offsets;
    std::map<std::string, Eigen::Isometry3d> origins;
    for (std::size_t i = 0; i < result.joints.size() && i < frames.joint_names.size(); ++i) {
      if (result.joints[i].held.empty()) offsets[frames.joint_names[i]] = result.joints[i].offset;
      if (result.joints[i].origin_free) origins[frames.joint_names[i]] = result.joints[i].origin;
    }
    writeRobotUrdf(rig, offsets, dir, origins);
  }
  // The IMUs through their cameras, in the frame each camera is mounted in (the tool for one the arm moves).
  const bool imu_withheld = finishImus(args, rig, bag, [&](int s, std::string* why, std::string* parent) {
    if (!withheld[s].empty()) {
      *why = "withheld: " + withheld[s];
      return std::optional<Eigen::Isometry3d>();
    }
    *parent = frames.parentOf(s);
    return std::optional<Eigen::Isometry3d>(result.sensors[s]);
  });
  return any_withheld || imu_withheld ? 1 : 0;
}

// A rig of one camera and its IMU: no still poses; the camera where the rig gives it, or placed through the
// IMU when the IMU is the reference.
int runCameraImu(const vocal::CommandLine& args, const vocal::RigDescription& rig, const std::string& bag) {
  const vocal::RigSensorDescription& camera = rig.sensors.front();
  const std::vector<vocal::ImuCalibrationOutput> imus = calibrateImus(args, rig, bag, [&](int s, std::string* why, std::string*) {
    if (rig.sensors[s].pose) return rig.sensors[s].pose;
    *why = "the rig gives it no pose";
    return std::optional<Eigen::Isometry3d>();
  });
  std::optional<Eigen::Isometry3d> camera_in_rig = camera.pose;
  std::string camera_withheld;
  if (rig.reference_imu >= 0) {
    const vocal::ImuCalibrationOutput& reference = imus[rig.reference_imu];
    if (reference.withheld.empty()) {
      camera_in_rig = *reference.rig_from_imu * reference.result.camera_in_imu;
      printPose((camera.spec.name + " in " + rig.reference_frame).c_str(), *camera_in_rig, &reference.result.sigma, nullptr);
    } else {
      camera_withheld = "placed through imu '" + reference.name + "', which is withheld";
    }
  }
  bool any_withheld = !camera_withheld.empty();
  for (const vocal::ImuCalibrationOutput& imu : imus) any_withheld = any_withheld || !imu.withheld.empty();
  if (args.has("output-dir")) {
    const std::string dir = args.text("output-dir", "");
    {
      std::ofstream yaml(dir + "/calibration.yaml"), urdf(dir + "/calibration.urdf"), launch(dir + "/calibration.launch");
      yaml << "# vocal MSG-Cal result: pose of each sensor frame in " << rig.reference_frame << "\nreference_frame: " << rig.reference_frame
           << "\nsensors:\n  - name: " << camera.spec.name << "\n    type: camera\n    frame_id: " << camera.spec.frame_id
           << "\n    parent: " << rig.reference_frame << "\n";
      urdf << "<!-- vocal MSG-Cal result: paste into the robot's URDF -->\n";
      launch << "<launch>\n  <!-- vocal MSG-Cal result as static transforms -->\n";
      if (camera_in_rig) {
        const Eigen::Quaterniond q(camera_in_rig->rotation());
        const Eigen::Vector3d t = camera_in_rig->translation();
        yaml << std::setprecision(9) << "    translation: [" << t.x() << ", " << t.y() << ", " << t.z() << "]\n    rotation: [" << q.x() << ", "
             << q.y() << ", " << q.z() << ", " << q.w() << "]\n";
      }
      yaml << "    " << (rig.reference_imu >= 0 ? "placed_through: " + rig.imus[rig.reference_imu].name : std::string("held: true  # the rig's reference"))
           << "\n    published: " << (camera_withheld.empty() ? "true" : "false") << "\n";
      if (!camera_withheld.empty()) {
        yaml << "    withheld_because: " << vocal::yamlQuoted(camera_withheld) << "\n";
        urdf << "<!-- " << camera.spec.frame_id << " withheld: " << camera_withheld << " -->\n";
      } else if (camera_in_rig) {
        // As the still-pose outputs write their reference: held, and in the files with the rest.
        urdf << vocal::urdfFixedJoint(rig.reference_frame, camera.spec.frame_id, *camera_in_rig);
        launch << vocal::staticTransformNode(camera.spec.name + "_extrinsic", rig.reference_frame, camera.spec.frame_id, *camera_in_rig);
      }
      launch << "</launch>\n";
      if (!yaml.flush() || !urdf.flush() || !launch.flush()) throw vocal::InputError(dir + ": cannot write calibration output");
    }
    writeImuOutputs(dir, rig, imus);
  }
  return any_withheld ? 1 : 0;
}

int run(const vocal::CommandLine& args) {
  if (args.has("overlays") && !args.has("output-dir")) throw vocal::InputError("--overlays needs --output-dir (where the PNGs go)");
  const vocal::SpreadTolerance tolerance{positiveOption(args, "tolerance-mm", 10.0) / 1000, positiveOption(args, "tolerance-mrad", 10.0) / 1000};
  vocal::SessionMemoryOptions memory;
  memory.max_held_mb = args.number("max-held-mb", memory.max_held_mb);
  if (!(memory.max_held_mb >= 0.0)) throw vocal::InputError("option --max-held-mb: must be >= 0 (got " + args.text("max-held-mb", "") + ")");
  vocal::RigDescription rig = vocal::readRigDescription(args.positional()[0]);
  if (!rig.urdf_param.empty()) {
    throw vocal::InputError(args.positional()[0] + ": 'urdf_param: " + rig.urdf_param + "' names a parameter, which a bag does not hold: for "
                            "calibrate_rig give the robot's URDF file as 'urdf:' (rosparam get " + rig.urdf_param + " > robot.urdf)");
  }
  const std::string bag = args.positional()[1];
  if (args.has("output-dir")) vocal::makeFolders(args.text("output-dir", ""));  // before the work, not after
  if (args.has("imu-bag") && rig.imus.empty()) throw vocal::InputError("option --imu-bag: the rig has no sensor of type imu");
  // A camera and its IMU alone: no still poses (a camera an arm or joints move has them).
  if (!rig.imus.empty() && rig.sensors.size() == 1 && !rig.handEye() && rig.jointedMounts().chains.empty()) return runCameraImu(args, rig, bag);
  // An IMU as the reference: calibrated first, its camera placed through it holds the still poses' frame.
  std::optional<std::vector<vocal::ImuCalibrationOutput>> imus_first;
  if (rig.reference_imu >= 0) {
    imus_first = calibrateImus(args, rig, bag, [](int, std::string* why, std::string*) {
      *why = "it is placed through the reference IMU";
      return std::optional<Eigen::Isometry3d>();
    });
    const vocal::ImuCalibrationOutput& reference = (*imus_first)[rig.reference_imu];
    vocal::RigSensorDescription& camera = rig.sensors[rig.imus[rig.reference_imu].camera];
    if (!reference.withheld.empty()) {
      throw vocal::InputError("the rig's reference, imu '" + reference.name + "', is not calibrated against camera '" + camera.spec.name +
                              "' (" + reference.withheld + "), so nothing can be placed in " + rig.reference_frame);
    }
    camera.pose = *reference.rig_from_imu * reference.result.camera_in_imu;
    printPose((camera.spec.name + " in " + rig.reference_frame).c_str(), *camera.pose, &reference.result.sigma, nullptr);
    std::printf("  (placed through the reference imu '%s': the still poses' reference)\n", reference.name.c_str());
  }
  vocal::RingOffsetOptions ring_offset_options;
  ring_offset_options.enabled = !args.has("no-ring-offsets");
  vocal::CalibrationSession session(rig, {}, {}, ring_offset_options, memory);
  const bool quiet = args.has("quiet");
  // On a terminal one line counts up; in a log, a line per thousand messages.
  const bool terminal = isatty(fileno(stderr));
  const vocal::BagReadSummary read = vocal::readCalibrationBag(bag, &session, [&](std::size_t n) {
    if (quiet) return;
    if (terminal && n % 50 == 0) std::fprintf(stderr, "\rreading message %zu", n);
    if (!terminal && n % 1000 == 0) std::fprintf(stderr, "read %zu messages\n", n);
  }, args.integer("threads", 0));
  if (!quiet && terminal) std::fprintf(stderr, "\r");
  std::printf("%zu messages on the rig's topics, %zu dropped\n", read.messages, read.dropped);
  for (const std::string& problem : read.problems) std::printf("  dropped: %s\n", problem.c_str());
  if (const std::optional<vocal::HandEyeRig> arm = rig.handEye()) return runHandEye(args, rig, *arm, session, bag, tolerance);
  const bool jointed = !rig.jointedMounts().chains.empty();
  if (jointed && session.jointReadings() == 0) {
    std::string names;
    for (const vocal::JointDescription& joint : rig.joints) names += (names.empty() ? "" : ", ") + joint.name;
    throw vocal::InputError(bag + ": the rig has sensors behind joints, but the bag has no sensor_msgs/JointState on " + rig.joint_states_topic +
                            " naming any of them (" + names + "); record the robot's joint states, or set joint_states_topic in the rig");
  }
  vocal::CalibrationOptions options;
  options.consensus_filter = !args.has("no-filter");
  options.board_edges.enabled = !args.has("no-edges");
  options.intrinsics.enabled = args.has("refine-intrinsics");
  options.trust.isolate = !args.has("no-isolation");
  // Before association: the lidars' board points depend on whether their offsets are applied.
  const std::vector<std::optional<vocal::RingOffsets>> ring_offsets = session.chooseRingOffsets(options);
  const std::vector<vocal::TargetObservation> associated = session.associatedObservations();
  int poses = 0;
  for (const auto& o : associated) poses = std::max(poses, o.target_pose + 1);
  std::printf("%d still target poses\n", poses);
  // Applied offsets always; with --report the others' too (how far each sensor's runs lie from the reference's).
  for (const vocal::ClockOffset& clock : session.clockOffsets())
    if (clock.applied || !clock.refused.empty() || args.has("report")) std::printf("clock: %s\n", vocal::describeClockOffset(clock, rig.specs()).c_str());
  const std::vector<vocal::SensorDataCounts> counts = session.counts();
  const std::vector<std::map<std::string, int>> refused = refusedByCheck(rig, session);
  for (std::size_t s = 0; s < rig.sensors.size(); ++s) {
    const vocal::SensorDataCounts& c = counts[s];
    std::printf("  %-12s %-8s target in %d of %d messages", rig.sensors[s].spec.name.c_str(),
                vocal::sensorTypeName(rig.sensors[s].spec.type).c_str(), c.target_found, c.received);
    if (c.only_background > 0) std::printf(" (%d more with only static board-shaped segments: room, furniture)", c.only_background);
    if (c.not_kept > 0) std::printf(" (%d more skipped: the session was full)", c.not_kept);
    if (c.views_with_corners_left_out > 0)
      std::printf(" (%d with a corner the detector misplaced, left out of the board's pose)", c.views_with_corners_left_out);
    // A range sensor that missed the board in most messages: why, here and not only with --report (the
    // calibration may stop for want of its views before the report).
    if (2 * c.target_found < c.received && !refused[s].empty()) {
      std::vector<std::pair<int, std::string>> most;
      for (const auto& [check, count] : refused[s]) most.emplace_back(count, check);
      std::sort(most.rbegin(), most.rend());
      std::printf("; the others refused as");
      for (std::size_t k = 0; k < most.size(); ++k) std::printf("%s %s %d", k ? "," : ":", most[k].second.c_str(), most[k].first);
      std::printf(" (the rig's board: %.3f x %.3f m)", rig.target.width, rig.target.height);
    }
    std::printf("\n");
  }
  std::printf("memory: %s%s\n", session.memorySummary().c_str(), session.memory().full ? " (raise --max-held-mb to keep them)" : "");
  printRingOffsets(rig, ring_offsets);
  const vocal::CalibrationResult result = session.calibrate(associated, options);
  if (jointed) printJoints(rig, session, result);
  std::printf("%-12s %10s %10s %10s %10s %10s %10s %10s   %s\n", "sensor", "x", "y", "z", "qx", "qy", "qz", "qw",
              "sigma t (mm) / r (mrad), rms (mm), observations (rejected), off the others' board (mm / mrad)");
  for (std::size_t s = 0; s < rig.sensors.size(); ++s) {
    const vocal::SensorCalibration& c = result.sensors[s];
    const Eigen::Vector3d t = c.reference_from_sensor.translation();
    const Eigen::Quaterniond q(c.reference_from_sensor.rotation());
    const std::string parent = vocal::sensorParent(result, s, rig.reference_frame);
    std::printf("%-12s %10.5f %10.5f %10.5f %10.6f %10.6f %10.6f %10.6f   %.2f / %.2f, %.2f, %d (%d), %.1f / %.1f%s%s\n",
                rig.sensors[s].spec.name.c_str(), t.x(), t.y(), t.z(), q.x(), q.y(), q.z(), q.w(),
                1000 * c.standard_deviation.head<3>().norm(), 1000 * c.standard_deviation.tail<3>().norm(), 1000 * c.rms,
                c.observations, c.rejected_observations, 1000 * c.disagreement_distance, 1000 * c.disagreement_angle,
                c.isolated ? " (isolated)" : "", parent == rig.reference_frame ? "" : (" (in " + parent + ")").c_str());
  }
  std::printf("rms point-to-plane: %.3f mm\n", 1000 * result.rms);
  for (std::size_t s = 0; s < rig.sensors.size(); ++s) {
    const vocal::SensorCalibration& c = result.sensors[s];
    if (c.intrinsicsRefined()) printRefinedIntrinsics(rig.sensors[s].spec.name, c.given_intrinsics, c.refined_intrinsics, c.intrinsics_sigma);
    if (c.beam_solved) printBeamRadius(rig.sensors[s].spec.name, c.beam_radius);
  }
  // The result re-solved once without each still pose: how far each sensor moves (one solve per pose).
  const std::vector<vocal::SensorSpec> specs = rig.specs();
  const std::optional<vocal::PoseJackknife> spread =
      printSpreadAndVerdicts(specs, rig.reference_sensor, associated, session.calibrationOptions(options), result, tolerance);
  if (args.has("report")) printReport(rig, refused, associated, result, poses);
  const std::vector<std::string> withheld = withholdAndWrite(args, rig, specs, rig.reference_sensor, result, spread, &ring_offsets, tolerance);
  const bool any_withheld = std::any_of(withheld.begin(), withheld.end(), [](const std::string& why) { return !why.empty(); });
  if (args.has("output-dir") && args.has("overlays"))
    printOverlaySummary(rig, vocal::writeCalibrationOverlays(bag, rig, associated, result, args.text("output-dir", "")));
  const bool imu_withheld = finishImus(
      args, rig, bag,
      [&](int s, std::string* why, std::string* parent) {
        *why = withheld[s].empty() ? std::string() : "withheld: " + withheld[s];
        *parent = vocal::sensorParent(result, s, rig.reference_frame);  // a camera on a head: its link
        return withheld[s].empty() ? std::optional<Eigen::Isometry3d>(result.sensors[s].reference_from_sensor) : std::nullopt;
      },
      imus_first ? &*imus_first : nullptr);
  // Non-zero when a sensor was left out, so a script applying the result notices.
  return any_withheld || imu_withheld ? 1 : 0;
}
}  // namespace

int main(int argc, char** argv) {
  return vocal::runTool("calibrate_rig", kUsage, run, argc, argv, {"output-dir", "tolerance-mm", "tolerance-mrad", "max-held-mb", "threads", "imu-bag"}, {"no-filter", "quiet", "report", "edges", "no-edges", "refine-intrinsics", "overlays", "no-ring-offsets", "publish-uncertain", "no-isolation", "one-graph"}, 2);
}
