#include "vocal/calibration/pairwise_initialization.h"

#include <sstream>

#include <Eigen/SVD>

#include "vocal/core/errors.h"

namespace vocal {

Eigen::Isometry3d alignPlanes(const std::vector<Plane>& in_a, const std::vector<Plane>& in_b, const std::string& what) {
  if (in_a.size() != in_b.size() || in_a.size() < 3) {
    throw InputError(what + ": " + std::to_string(std::min(in_a.size(), in_b.size())) +
                     " shared target poses, at least 3 with non-parallel planes are needed");
  }
  const int n = static_cast<int>(in_a.size());
  Eigen::MatrixXd normals_a(n, 3);
  for (int i = 0; i < n; ++i) normals_a.row(i) = in_a[i].normal.transpose();
  // The normals must span 3D, or translation along the missing direction is free.
  const Eigen::JacobiSVD<Eigen::MatrixXd> spread(normals_a, Eigen::ComputeFullV);
  const Eigen::Vector3d singular = spread.singularValues();
  if (singular[2] < 0.05 * singular[0]) {
    std::ostringstream message;
    message.precision(3);
    const Eigen::Vector3d weak = spread.matrixV().col(2);
    message << what << ": the target planes are too close to parallel (normal spread " << singular[2] / singular[0]
            << " < 0.05): translation along [" << weak.x() << " " << weak.y() << " " << weak.z()
            << "] is unconstrained; tilt the target more between poses";
    throw InputError(message.str());
  }
  Eigen::Matrix3d correlation = Eigen::Matrix3d::Zero();
  for (int i = 0; i < n; ++i) correlation += in_a[i].normal * in_b[i].normal.transpose();
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(correlation, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d S = Eigen::Matrix3d::Identity();
  if ((svd.matrixU() * svd.matrixV().transpose()).determinant() < 0.0) S(2, 2) = -1.0;
  Eigen::Isometry3d a_from_b = Eigen::Isometry3d::Identity();
  a_from_b.linear() = svd.matrixU() * S * svd.matrixV().transpose();
  // n_a . t = d_b - d_a for every plane.
  Eigen::VectorXd offsets(n);
  for (int i = 0; i < n; ++i) offsets[i] = in_b[i].offset - in_a[i].offset;
  a_from_b.translation() = normals_a.colPivHouseholderQr().solve(offsets);
  return a_from_b;
}

}  // namespace vocal
