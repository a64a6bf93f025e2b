#pragma once
// A frame the joints move (the tool, a forearm, a head's link) in the arm's graph
// (hand_eye_calibration.h): its block per still pose tied to its chain at that pose's readings.

#include <vector>

#include <Eigen/Geometry>

#include "vocal/calibration/joint_chain.h"
#include "vocal/calibration/solver/rotation_error.h"

namespace vocal {

// The frame's block (blocks 0, 1) against the chain's pose at the station's readings plus the offsets
// (the next blocks, one per chain joint) plus the station's reading corrections (the next, one per chain
// joint), held within 10 um / 10 urad: the frame is the chain's pose, kept as a block so that the views'
// residuals stay as they are whatever moves their frames.
// Joints of the chain with a free origin (JointDescription::free_origin) add their origin's correction
// (a block of 6 each, in the chain's order) after those.
// `mounted`: the frame is a sensor's on the chain's last link, the chain's pose times the sensor's mount
// (blocks 2, 3: rotation, translation; the offsets and the rest after them).
struct LinkFromJointsResidual {
  const std::vector<JointDescription>* joints;
  std::vector<int> chain;        // from the base to the frame (jointChain)
  std::vector<double> readings;  // per joint of `chain`
  bool mounted = false;

  template <typename T>
  bool operator()(T const* const* blocks, T* residual) const {
    const int first = mounted ? 4 : 2;
    std::vector<const T*> origins(chain.size(), nullptr);
    T const* const* free_origin = blocks + first + 2 * chain.size();
    for (std::size_t i = 0; i < chain.size(); ++i)
      if ((*joints)[chain[i]].free_origin) origins[i] = *free_origin++;
    Eigen::Quaternion<T> q;
    Eigen::Matrix<T, 3, 1> t;
    correctedChainTransform<T>(*joints, chain, readings.data(), blocks + first, blocks + first + chain.size(), &q, &t, origins.data());
    if (mounted) {
      const Eigen::Map<const Eigen::Quaternion<T>> mount_q(blocks[2]);
      const Eigen::Map<const Eigen::Matrix<T, 3, 1>> mount_t(blocks[3]);
      t = t + q * mount_t;
      q = q * mount_q;
    }
    const Eigen::Map<const Eigen::Quaternion<T>> frame_q(blocks[0]);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> frame_t(blocks[1]);
    constexpr double kTight = 1e-5;
    Eigen::Map<Eigen::Matrix<T, 6, 1>> out(residual);
    out.template head<3>() = rotationBetween(q, Eigen::Quaternion<T>(frame_q)) / T(kTight);
    out.template tail<3>() = (frame_t - t) / T(kTight);
    return true;
  }
};

}  // namespace vocal
