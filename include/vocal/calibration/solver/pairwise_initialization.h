#pragma once
// Closed-form extrinsic between two sensors from the planes both saw: rotation from matched normals
// (SVD), translation from the plane offsets (least squares).

#include <string>
#include <vector>

#include "vocal/calibration/plane.h"

namespace vocal {

// The board's centre on each matched plane, as each sensor saw it (board_outline.h; a camera's pattern).
struct BoardCentres {
  std::vector<Eigen::Vector3d> in_a, in_b;
  double weight = 0.2;  // of a centre's equation against an offset's (centres are a few times less precise)
};

// a_from_b with n_a = R n_b and d_a = d_b - n_a . t for every matched pair. Throws InputError naming
// `what` when fewer than 3 planes are matched or their normals do not span 3D (target poses too
// close to parallel), saying which direction is unconstrained - unless `centres` are given: then
// c_a = R c_b + t fixes translation along it (the rotation still needs two non-parallel normals).
Eigen::Isometry3d alignPlanes(const std::vector<Plane>& in_a, const std::vector<Plane>& in_b, const std::string& what,
                              const BoardCentres* centres = nullptr);

// rig_from_laser for a 2D laser (points in its z = 0 scan plane) from its scan points on target planes
// known in the rig frame: each point p on plane (n, d) gives n . (x r1 + y r2 + t) = -d, linear in the
// first two rotation columns and t; the solution is projected onto a rotation and t solved again.
// Throws InputError naming `what` when the lines do not fix the pose (fewer than 5 target poses, or
// lines too close to parallel). With the boards' poses and each scan's two ends on their edges, a
// board tilted only up and down still fixes the laser: a scan crossing the board between opposite
// edges has its midpoint on the board's centre line and spans the board's side.
struct ScanEnds {
  std::vector<Eigen::Isometry3d> rig_from_board;   // per scan; x along the board's width
  std::vector<std::vector<Eigen::Vector3d>> ends;  // per scan: its outline points in beam order (2 when both ends are seen)
  double board_width = 0.0, board_height = 0.0;
  double weak_spread = 0.15;  // the ends are used when the normals' spread is below (observability.h's bound)
  double weight = 1.0;        // of an end equation against a scan point's
};
Eigen::Isometry3d alignLaserLines(const std::vector<Plane>& planes_in_rig,
                                  const std::vector<std::vector<Eigen::Vector3d>>& scan_points, const std::string& what,
                                  const ScanEnds* scan_ends = nullptr);

}  // namespace vocal
