#pragma once
// A residual of a sensor behind joints in the still-pose graph (graph_calibration.h): the sensor's pose in
// the rig frame composed from its chain at a still pose's readings and its mount on the chain's last link,
// handed to a residual written for a rigid sensor. Eigen only.

#include <cstddef>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "vocal/calibration/joint_chain.h"

namespace vocal {

// Residual's blocks are (sensor rotation, sensor translation, then kBlocks more); this residual's are (mount
// rotation, mount translation, Residual's kBlocks, the chain's joint offsets, the pose's reading
// corrections, the free origins' corrections (JointDescription::free_origin) in chain order), for
// ceres::DynamicAutoDiffCostFunction: the sensor's pose is the chain's at `positions` plus the offsets and
// corrections, times its mount.
template <typename Residual, int kBlocks>
struct ThroughJoints {
  Residual residual;
  const std::vector<JointDescription>* joints;
  std::vector<int> chain;
  std::vector<double> positions;

  template <typename T>
  bool operator()(T const* const* blocks, T* out) const {
    Eigen::Quaternion<T> chain_rotation;
    Eigen::Matrix<T, 3, 1> chain_translation;
    const int first = 2 + kBlocks;
    std::vector<const T*> origins(chain.size(), nullptr);
    T const* const* free_origin = blocks + first + 2 * chain.size();
    for (std::size_t i = 0; i < chain.size(); ++i)
      if ((*joints)[chain[i]].free_origin) origins[i] = *free_origin++;
    correctedChainTransform<T>(*joints, chain, positions.data(), blocks + first, blocks + first + chain.size(), &chain_rotation,
                               &chain_translation, origins.data());
    const Eigen::Map<const Eigen::Quaternion<T>> mount_rotation(blocks[0]);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> mount_translation(blocks[1]);
    const Eigen::Quaternion<T> rotation = chain_rotation * mount_rotation;
    const Eigen::Matrix<T, 3, 1> translation = chain_translation + chain_rotation * mount_translation;
    return call(rotation.coeffs().data(), translation.data(), blocks + 2, out, std::make_index_sequence<kBlocks>());
  }
  template <typename T, std::size_t... I>
  bool call(const T* rotation, const T* translation, T const* const* rest, T* out, std::index_sequence<I...>) const {
    return residual(rotation, translation, rest[I]..., out);
  }
};

}  // namespace vocal
