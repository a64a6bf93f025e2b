#include "vocal/odometry/keyframe_window.h"

#include <algorithm>
#include <memory>
#include <set>

#include <ceres/ceres.h>

#include "vocal/core/errors.h"

namespace vocal {

namespace {
// The error of one link: the twist x with (a^-1 b) = exp(x) from_T_to, to first order
// [translation; 2 quaternion vector] of (a^-1 b) from_T_to^-1, scaled by the square root of the link's
// information (L^T with A = L L^T), so that the squared norm is x^T A x.
struct LinkError {
  LinkError(const Eigen::Isometry3d& from_T_to, const Matrix6d& sqrt_information)
      : measured_rotation(from_T_to.linear()), measured_translation(from_T_to.translation()),
        sqrt_information(sqrt_information) {}

  template <typename T>
  bool operator()(const T* q_a_data, const T* p_a_data, const T* q_b_data, const T* p_b_data, T* residual) const {
    const Eigen::Map<const Eigen::Quaternion<T>> q_a(q_a_data), q_b(q_b_data);
    const Eigen::Map<const Eigen::Matrix<T, 3, 1>> p_a(p_a_data), p_b(p_b_data);
    const Eigen::Quaternion<T> q_ab = q_a.conjugate() * q_b;
    const Eigen::Matrix<T, 3, 1> p_ab = q_a.conjugate() * (p_b - p_a);
    Eigen::Quaternion<T> q_error = q_ab * measured_rotation.conjugate().template cast<T>();
    if (q_error.w() < T(0)) q_error.coeffs() = -q_error.coeffs();  // the same rotation, near identity
    Eigen::Matrix<T, 6, 1> error;
    error.template head<3>() = p_ab - (q_error * measured_translation.template cast<T>());
    error.template tail<3>() = T(2) * q_error.vec();
    Eigen::Map<Eigen::Matrix<T, 6, 1>> weighted(residual);
    weighted = sqrt_information.template cast<T>() * error;
    return true;
  }

  Eigen::Quaterniond measured_rotation;
  Eigen::Vector3d measured_translation;
  Matrix6d sqrt_information;
};

struct PoseBlock {
  Eigen::Quaterniond rotation;
  Eigen::Vector3d translation;
};
}  // namespace

KeyframeWindow::KeyframeWindow(int size) : size_(size) {
  if (size < 2) throw InputError("keyframe window: size " + std::to_string(size) + " < 2 (nothing to refine)");
}

void KeyframeWindow::clear() {
  ids_.clear();
  poses_.clear();
  links_.clear();
  relinked_ = false;
}

void KeyframeWindow::addKeyframe(int id, const Eigen::Isometry3d& pose) {
  ids_.push_back(id);
  poses_[id] = pose;
  while (static_cast<int>(ids_.size()) > size_) {
    const int gone = ids_.front();
    ids_.pop_front();
    poses_.erase(gone);
    links_.erase(std::remove_if(links_.begin(), links_.end(),
                                [gone](const KeyframeLink& l) { return l.from_id == gone || l.to_id == gone; }),
                 links_.end());
  }
}

void KeyframeWindow::addLink(const KeyframeLink& link) {
  if (!poses_.count(link.from_id) || !poses_.count(link.to_id) || link.from_id == link.to_id) return;
  if (!link.information.allFinite() || !link.from_T_to.matrix().allFinite()) return;
  for (KeyframeLink& known : links_) {
    if (known.from_id == link.from_id && known.to_id == link.to_id) {
      known = link;  // the same pair solved again (finer): the newer solve stands for it
      relinked_ = true;
      return;
    }
  }
  links_.push_back(link);
}

std::optional<Eigen::Isometry3d> KeyframeWindow::pose(int id) const {
  const auto found = poses_.find(id);
  if (found == poses_.end()) return std::nullopt;
  return found->second;
}

std::vector<int> KeyframeWindow::ids() const { return {ids_.begin(), ids_.end()}; }

bool KeyframeWindow::optimise() {
  // Links that form no loop (a chain, a tree) fit exactly: nothing to refine, unless one was solved again.
  std::set<int> linked;
  for (const KeyframeLink& link : links_) linked.insert({link.from_id, link.to_id});
  if (links_.empty() || (links_.size() < linked.size() && !relinked_)) return false;
  relinked_ = false;
  std::map<int, PoseBlock> blocks;
  for (const auto& [id, pose] : poses_) blocks[id] = {Eigen::Quaterniond(pose.linear()).normalized(), pose.translation()};
  ceres::Problem problem;
  for (const KeyframeLink& link : links_) {
    // The square root of the information: its Cholesky factor (a singular one keeps its eigen form).
    const Eigen::LLT<Matrix6d> llt(link.information);
    Matrix6d sqrt_information;
    if (llt.info() == Eigen::Success) {
      sqrt_information = llt.matrixL().transpose();
    } else {
      const Eigen::SelfAdjointEigenSolver<Matrix6d> eigen(link.information);
      sqrt_information = eigen.eigenvalues().cwiseMax(0.0).cwiseSqrt().asDiagonal() * eigen.eigenvectors().transpose();
    }
    PoseBlock &a = blocks[link.from_id], &b = blocks[link.to_id];
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<LinkError, 6, 4, 3, 4, 3>(new LinkError(link.from_T_to, sqrt_information)),
                             nullptr, a.rotation.coeffs().data(), a.translation.data(), b.rotation.coeffs().data(),
                             b.translation.data());
  }
  // The window's anchor: its oldest linked keyframe (the odometry before it is not revisited).
  const int oldest_linked = *std::find_if(ids_.begin(), ids_.end(), [&](int id) { return linked.count(id) > 0; });
  for (auto& [id, block] : blocks) {
    if (!problem.HasParameterBlock(block.rotation.coeffs().data())) continue;
    problem.SetManifold(block.rotation.coeffs().data(), new ceres::EigenQuaternionManifold());
    if (id == oldest_linked) {
      problem.SetParameterBlockConstant(block.rotation.coeffs().data());
      problem.SetParameterBlockConstant(block.translation.data());
    }
  }
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_QR;
  options.max_num_iterations = 10;
  options.num_threads = 1;
  options.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  if (!summary.IsSolutionUsable()) return false;
  for (const auto& [id, block] : blocks) {
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.linear() = block.rotation.normalized().toRotationMatrix();
    pose.translation() = block.translation;
    poses_[id] = pose;
  }
  return true;
}

}  // namespace vocal
