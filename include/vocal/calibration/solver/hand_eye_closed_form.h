// OpenCV's closed-form hand-eye solution (cv::calibrateHandEye) for a camera on a moving frame over a
// board that stands still: the start of both the arm's graph and the still-pose graph's camera on a tool.

#pragma once

#include <vector>

#include <Eigen/Geometry>

namespace vocal {

constexpr int kParkHandEye = 1;  // cv::CALIB_HAND_EYE_PARK

// frame <- camera from the frame's pose in the base at each still pose (base <- frame) and the board the
// camera saw then (camera <- board). `method`: a cv::HandEyeCalibrationMethod (0 Tsai, 1 Park, 2 Horaud,
// 3 Andreff, 4 Daniilidis). A camera fixed while the board rides the frame: pass frame <- base instead.
Eigen::Isometry3d openCvHandEye(const std::vector<Eigen::Isometry3d>& base_from_frame,
                                const std::vector<Eigen::Isometry3d>& camera_from_board, int method);

}  // namespace vocal
