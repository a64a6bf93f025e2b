#pragma once
// What MSG-Cal works on: the sensors of a rig and their observations of the planar target.

#include <string>
#include <vector>

#include <Eigen/Geometry>

namespace vocal {

enum class SensorType { kCamera, kRgbd, kLidar3d, kLaser2d };

SensorType parseSensorType(const std::string& name);  // camera, rgbd, lidar3d, laser2d
std::string sensorTypeName(SensorType type);

struct SensorSpec {
  std::string name;
  SensorType type = SensorType::kRgbd;
  std::string frame_id;
};

// A camera's measurement of the target plane: the pattern's pose from its corners (PnP) and the
// covariance of the plane it fixes, from the reprojection error. The plane is measured as the pattern
// normal's components along the pattern's own x and y axes (its tilt, radians) and the distance of
// the pattern's centre along the normal (metres); PnP's tilt is far less certain than its offset, and
// the two are correlated, so the graph weights this measurement by the full 3x3 covariance.
struct PlaneMeasurement {
  Eigen::Isometry3d sensor_from_pattern = Eigen::Isometry3d::Identity();
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Identity();  // of (tilt x, tilt y, centre distance)
  // Of the whole pose, perturbed as R exp([w]x), t + dt, in the order (w, dt): what a camera on an arm
  // (hand_eye_calibration.h) is weighted by, where the board's place within its plane counts too.
  Eigen::Matrix<double, 6, 6> pose_covariance = Eigen::Matrix<double, 6, 6>::Identity();
  // What the corners say of the intrinsics (fx, fy, cx, cy) the pose was fitted with, to first order in
  // their relative change dk = (dfx / fx, dfy / fy, dcx / fx, dcy / fy), so a graph can refine them
  // without the corners: the pose's perturbation (w, dt) per dk, and the corners' own misfit beyond the
  // pose's as |evidence_matrix dk + evidence_offset|^2 (pixel-noise whitened; zero: no evidence).
  Eigen::Vector4d intrinsics = Eigen::Vector4d::Zero();  // (fx, fy, cx, cy) as used; zero: not from corners
  Eigen::Matrix<double, 6, 4> pose_per_intrinsics = Eigen::Matrix<double, 6, 4>::Zero();
  Eigen::Matrix4d evidence_matrix = Eigen::Matrix4d::Zero();
  Eigen::Vector4d evidence_offset = Eigen::Vector4d::Zero();
};

// The view as it reads when the board's corners were found in the other order (a checkerboard is found
// either way round): the board turned 180 degrees about its normal; its covariances and intrinsics
// response follow the pattern frame.
PlaneMeasurement turnedHalfway(const PlaneMeasurement& view);

// One sensor's view of the target while it was held at one pose: points on the target in the sensor
// frame (a depth or lidar sensor's inliers, a 2D laser's scan points, a camera's pattern corners
// placed by its pose estimate).
struct TargetObservation {
  int sensor = 0;       // index into the sensor list
  int target_pose = 0;  // which still period of the target (association result)
  std::vector<Eigen::Vector3d> points;
  // Cameras: one measurement per view (several when still views are pooled). The graph then uses
  // these instead of the points, which all share each view's plane error; range sensors leave it
  // empty and are weighted by their points' own scatter about the fitted plane.
  std::vector<PlaneMeasurement> plane_measurements;
  // Range sensors: points on the board's edges (board_outline.h), sensor frame; used when the graph
  // holds the board's outline as well as its plane (CalibrationOptions::board_edges).
  std::vector<Eigen::Vector3d> outline;
  // Seconds: the first and last message of the still run it pools (0 when not associated by time), so
  // a pose can be found again in the recording (overlays) and compared across recordings.
  double first_stamp = 0.0, last_stamp = 0.0;
  // A sensor mounted behind joints (JointedMounts, graph_calibration.h): each joint of its chain's
  // position while it was still (radians or metres, as the encoders read them); empty for a rigid mount.
  std::vector<double> joint_positions;
};

}  // namespace vocal
