#include "vocal/calibration/solver/hand_eye_closed_form.h"

#include <opencv2/calib3d.hpp>

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

}  // namespace vocal
