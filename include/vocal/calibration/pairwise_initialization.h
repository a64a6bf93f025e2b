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

}  // namespace vocal
