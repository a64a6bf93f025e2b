#pragma once
// A frame the joints move (the tool, a forearm, a head's link) in the arm's graph
// (hand_eye_calibration.h): its block per still pose tied to its chain at that pose's readings.

#include <vector>

#include <Eigen/Geometry>

#include "vocal/calibration/joint_chain.h"
#include "vocal/calibration/solver/rotation_error.h"

namespace vocal {

// The frame's block (blocks 0, 1) against the chain's pose at the station's readings plus the offsets
// (blocks 2...) plus the station's reading corrections (the next blocks, one per chain joint each), held
// within 10 um / 10 urad: the frame is the chain's pose, kept as a block so that the views' residuals stay
// as they are whatever moves their frames.
// Joints of the chain with a free origin (JointDescription::free_origin) add their origin's correction
// (a block of 6 each, in the chain's order) after those.
struct LinkFromJointsResidual {
  const std::vector<JointDescription>* joints;
  std::vector<int> chain;        // from the base to the frame (jointChain)
  std::vector<double> readings;  // per joint of `chain`

  template <typename T>
  bool operator()(T const* const* blocks, T* residual) const {
    std::vector<const T*> origins(chain.size(), nullptr);
    T const* const* free_origin = blocks + 2 + 2 * chain.size();
    for (std::size_t i = 0; i < chain.size(); ++i)
      if ((*joints)[chain[i]].free_origin) origins[i] = *free_origin++;
    Eigen::Quaternion<T> q;
    Eigen::Matrix<T, 3, 1> t;
    correctedChainTransform<T>(*joints, chain, readings.data(), blocks + 2, blocks + 2 + chain.size(), &q, &t, origins.data());
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
