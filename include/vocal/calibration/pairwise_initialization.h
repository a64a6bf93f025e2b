#pragma once
// Closed-form extrinsic between two sensors from the planes both saw: rotation from matched normals
// (SVD), translation from the plane offsets (least squares).

#include <string>
#include <vector>

#include "vocal/calibration/plane.h"

namespace vocal {

// a_from_b with n_a = R n_b and d_a = d_b - n_a . t for every matched pair. Throws InputError naming
// `what` when fewer than 3 planes are matched or their normals do not span 3D (target poses too
// close to parallel), saying which direction is unconstrained.
Eigen::Isometry3d alignPlanes(const std::vector<Plane>& in_a, const std::vector<Plane>& in_b, const std::string& what);

// rig_from_laser for a 2D laser (points in its z = 0 scan plane) from its scan points on target planes
// known in the rig frame: each point p on plane (n, d) gives n . (x r1 + y r2 + t) = -d, linear in the
// first two rotation columns and t; the solution is projected onto a rotation and t solved again.
// Throws InputError naming `what` when the lines do not fix the pose (fewer than 5 target poses, or
// lines too close to parallel).
Eigen::Isometry3d alignLaserLines(const std::vector<Plane>& planes_in_rig,
                                  const std::vector<std::vector<Eigen::Vector3d>>& scan_points, const std::string& what);

}  // namespace vocal
