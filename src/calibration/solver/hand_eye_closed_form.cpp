#include "vocal/calibration/solver/hand_eye_closed_form.h"

#include <algorithm>

#include <opencv2/calib3d.hpp>

#include "vocal/core/se3.h"

namespace vocal {

Eigen::Isometry3d openCvHandEye(const std::vector<Eigen::Isometry3d>& base_from_frame,
                                const std::vector<Eigen::Isometry3d>& camera_from_board, int method) {
  std::vector<cv::Mat> frame_rotations, frame_translations, board_rotations, board_translations;
  const auto rotationMat = [](const Eigen::Matrix3d& r) {
    cv::Mat m(3, 3, CV_64F);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) m.at<double>(i, j) = r(i, j);
    return m;
  };
  const auto vectorMat = [](const Eigen::Vector3d& v) { return cv::Mat((cv::Mat_<double>(3, 1) << v.x(), v.y(), v.z())); };
  for (std::size_t k = 0; k < base_from_frame.size() && k < camera_from_board.size(); ++k) {
    frame_rotations.push_back(rotationMat(base_from_frame[k].linear()));
    frame_translations.push_back(vectorMat(base_from_frame[k].translation()));
    board_rotations.push_back(rotationMat(camera_from_board[k].linear()));
    board_translations.push_back(vectorMat(camera_from_board[k].translation()));
  }
  cv::Mat rotation, translation;
  cv::calibrateHandEye(frame_rotations, frame_translations, board_rotations, board_translations, rotation, translation,
                       static_cast<cv::HandEyeCalibrationMethod>(method));
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) pose.linear()(i, j) = rotation.at<double>(i, j);
    pose.translation()[i] = translation.at<double>(i);
  }
  return pose;
}

std::vector<HandEyeClosedForm> openCvHandEyeMethods(const std::vector<Eigen::Isometry3d>& base_from_frame,
                                                    const std::vector<Eigen::Isometry3d>& camera_from_board) {
  const std::pair<const char*, cv::HandEyeCalibrationMethod> methods[] = {{"Tsai", cv::CALIB_HAND_EYE_TSAI},
                                                                          {"Park", cv::CALIB_HAND_EYE_PARK},
                                                                          {"Horaud", cv::CALIB_HAND_EYE_HORAUD},
                                                                          {"Andreff", cv::CALIB_HAND_EYE_ANDREFF},
                                                                          {"Daniilidis", cv::CALIB_HAND_EYE_DANIILIDIS}};
  std::vector<HandEyeClosedForm> forms;
  for (const auto& [name, method] : methods) forms.push_back({name, openCvHandEye(base_from_frame, camera_from_board, method)});
  return forms;
}

bool handEyeClosedFormApplies(const JointedMounts& mounts, int camera) {
  return mounts.boardMoves() && mounts.moves(camera) == mounts.board_fixed;
}

HandEyeViews handEyeViews(const JointedMounts& mounts, const std::vector<TargetObservation>& observations, int camera,
                          const std::set<int>* poses) {
  HandEyeViews out;
  for (const TargetObservation& o : observations) {
    if (o.sensor != camera || o.plane_measurements.empty() || (poses && !poses->count(o.target_pose))) continue;
    out.frames.push_back(mounts.boardFrameAt(o.target_pose).inverse() * mounts.mountFrameAt(camera, o.target_pose, o.joint_positions));
    out.views.push_back(o.plane_measurements.front().sensor_from_pattern);
  }
  for (const Eigen::Isometry3d& frame : out.frames) out.turned = std::max(out.turned, rotationAngle(out.frames.front().inverse() * frame));
  return out;
}

}  // namespace vocal
