#pragma once
// Where a sensor and the board are mounted in an arm's graph (hand_eye_calibration.h): each fixed in the
// base frame or on a frame that moves - the tool, or for a sensor a link the joints move (a forearm, a
// head) - whose pose at each still pose is a block of the graph. Every view residual of that graph
// (camera_view_residual.h, range_view_residual.h, beam_range_view_residual.h, outline_view_residual.h)
// puts the board in the sensor's parent frame through it. Eigen only.

#include <utility>

#include <Eigen/Geometry>

namespace vocal {

struct FrameMounting {
  bool sensor_moves = true;
  bool board_moves = false;

  // The board in the sensor's parent frame, given the board in its own parent and the poses of the frames
  // the sensor and the board move with (each unused when it is fixed).
  template <typename T>
  void boardInSensorParent(const Eigen::Quaternion<T>& board_q, const Eigen::Matrix<T, 3, 1>& board_t, const Eigen::Quaternion<T>& sensor_frame_q,
                           const Eigen::Matrix<T, 3, 1>& sensor_frame_t, const Eigen::Quaternion<T>& board_frame_q,
                           const Eigen::Matrix<T, 3, 1>& board_frame_t, Eigen::Quaternion<T>* q, Eigen::Matrix<T, 3, 1>* t) const {
    *q = board_q;
    *t = board_t;
    if (board_moves) *t = board_frame_q * *t + board_frame_t, *q = board_frame_q * *q;
    if (sensor_moves) *t = sensor_frame_q.conjugate() * (*t - sensor_frame_t), *q = sensor_frame_q.conjugate() * *q;
  }
  // ... from the graph's blocks (the board's rotation and translation, the sensor's frame's, the board's
  // frame's), as (q, t).
  template <typename T>
  std::pair<Eigen::Quaternion<T>, Eigen::Matrix<T, 3, 1>> boardInSensorParent(T const* const* blocks) const {
    std::pair<Eigen::Quaternion<T>, Eigen::Matrix<T, 3, 1>> pose;
    boardInSensorParent(Eigen::Quaternion<T>(blocks[0]), Eigen::Matrix<T, 3, 1>(blocks[1]), Eigen::Quaternion<T>(blocks[2]),
                        Eigen::Matrix<T, 3, 1>(blocks[3]), Eigen::Quaternion<T>(blocks[4]), Eigen::Matrix<T, 3, 1>(blocks[5]), &pose.first,
                        &pose.second);
    return pose;
  }
  Eigen::Isometry3d boardInSensorParent(const Eigen::Isometry3d& board, const Eigen::Isometry3d& sensor_frame,
                                        const Eigen::Isometry3d& board_frame) const {
    Eigen::Isometry3d pose = board;
    if (board_moves) pose = board_frame * pose;
    if (sensor_moves) pose = sensor_frame.inverse() * pose;
    return pose;
  }
};

}  // namespace vocal
