#pragma once
// The local window of the odometry: the poses of the most recent keyframes refined together by a small
// pose graph (Ceres) of the dense keyframe-to-keyframe motions, each weighted by the information of its
// solve. The oldest keyframe of the window holds still, so this stays odometry: nothing older moves
// and no loop is closed.

#include <deque>
#include <map>
#include <optional>
#include <vector>

#include <Eigen/Geometry>

#include "vocal/core/se3.h"

namespace vocal {

// A dense motion between two keyframes of the window.
struct KeyframeLink {
  int from_id = 0;
  int to_id = 0;
  Eigen::Isometry3d from_T_to = Eigen::Isometry3d::Identity();
  // Of the motion's twist as a left perturbation (from_T_to <- exp(x) from_T_to): the solve's fused A.
  Matrix6d information = Matrix6d::Zero();
};

class KeyframeWindow {
 public:
  // `size`: the keyframes refined together (at least 2).
  explicit KeyframeWindow(int size = 4);

  // The newest keyframe, at its pose as tracked; the oldest beyond the window's size leaves it, with
  // the links that reach it.
  void addKeyframe(int id, const Eigen::Isometry3d& pose);
  // Ignored when either end is not in the window; a link between a pair already linked replaces theirs
  // (the pair solved again, e.g. finer).
  void addLink(const KeyframeLink& link);
  // Refines the poses of every keyframe in the window but the oldest linked one. False (poses kept)
  // when there is nothing to refine or the solver fails.
  bool optimise();

  std::optional<Eigen::Isometry3d> pose(int id) const;
  // Ids, oldest first.
  std::vector<int> ids() const;
  int linkCount() const { return static_cast<int>(links_.size()); }
  void clear();

 private:
  int size_;
  std::deque<int> ids_;
  std::map<int, Eigen::Isometry3d> poses_;
  std::vector<KeyframeLink> links_;
  bool relinked_ = false;  // a link replaced since the last optimise: even a chain is placed again
};

}  // namespace vocal
