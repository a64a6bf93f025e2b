// OpenCV's closed-form hand-eye solution (cv::calibrateHandEye) for a camera on a moving frame over a
// board that stands still, or fixed before a board the frame moves: the start of both the arm's graph and
// the still-pose graph's cameras on an arm, and the closed forms both print beside their result.

#pragma once

#include <set>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "vocal/calibration/calibration_types.h"
#include "vocal/calibration/joint_chain.h"

namespace vocal {

constexpr int kParkHandEye = 1;  // cv::CALIB_HAND_EYE_PARK

// frame <- camera from the frame's pose in the base at each still pose (base <- frame) and the board the
// camera saw then (camera <- board). `method`: a cv::HandEyeCalibrationMethod (0 Tsai, 1 Park, 2 Horaud,
// 3 Andreff, 4 Daniilidis). A camera fixed while the board rides the frame: pass frame <- base instead.
Eigen::Isometry3d openCvHandEye(const std::vector<Eigen::Isometry3d>& base_from_frame,
                                const std::vector<Eigen::Isometry3d>& camera_from_board, int method);

// A closed-form estimate of OpenCV's on the same poses.
struct HandEyeClosedForm {
  std::string method;  // Tsai, Park, Horaud, Andreff, Daniilidis
  Eigen::Isometry3d camera = Eigen::Isometry3d::Identity();
};

// Each of OpenCV's five methods on the same poses, in the order above.
std::vector<HandEyeClosedForm> openCvHandEyeMethods(const std::vector<Eigen::Isometry3d>& base_from_frame,
                                                    const std::vector<Eigen::Isometry3d>& camera_from_board);

// A camera's still-pose views as the closed form takes them in the still-pose graph (JointedMounts): per
// still pose the board's frame carried into the camera's mount frame (`frames`: the base for a camera on
// the arm over a board lying still, the tool's inverse for a fixed camera before the board on the arm) and
// its first view of the board; `turned`, the largest turn between those frames (radians).
struct HandEyeViews {
  std::vector<Eigen::Isometry3d> frames, views;
  double turned = 0.0;
};
// Whether the closed form applies to `camera`: it moves with the arm over a board lying still, or stands
// fixed before the board on the arm (not one moving while the board moves too: the closed forms came out
// far off on such mixed motions, a head's camera before the arm's board).
bool handEyeClosedFormApplies(const JointedMounts& mounts, int camera);
// `camera`'s views among `observations` at the still poses `poses` (all where null), with the joints'
// offsets as `mounts` holds them.
HandEyeViews handEyeViews(const JointedMounts& mounts, const std::vector<TargetObservation>& observations, int camera,
                          const std::set<int>* poses = nullptr);

}  // namespace vocal
