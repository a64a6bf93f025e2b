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

Eigen::Isometry3d alignLaserLines(const std::vector<Plane>& planes_in_rig,
                                  const std::vector<std::vector<Eigen::Vector3d>>& scan_points, const std::string& what) {
  if (planes_in_rig.size() != scan_points.size() || planes_in_rig.size() < 5) {
    throw InputError(what + ": " + std::to_string(std::min(planes_in_rig.size(), scan_points.size())) +
                     " target poses seen by the 2D laser and a placed sensor, at least 5 are needed (each scan line "
                     "gives 2 of the 9 linear constraints)");
  }
  std::size_t rows = 0;
  for (const auto& points : scan_points) rows += points.size();
  Eigen::MatrixXd M(rows, 9);
  Eigen::VectorXd rhs(rows);
  std::size_t row = 0;
  for (std::size_t k = 0; k < planes_in_rig.size(); ++k) {
    const Plane& plane = planes_in_rig[k];
    for (const Eigen::Vector3d& p : scan_points[k]) {
      M.row(row) << p.x() * plane.normal.transpose(), p.y() * plane.normal.transpose(), plane.normal.transpose();
      rhs[row++] = -plane.offset;
    }
  }
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(M, Eigen::ComputeThinU | Eigen::ComputeThinV);
  const Eigen::VectorXd singular = svd.singularValues();
  if (singular[8] < 1e-6 * singular[0]) {
    // The unconstrained combination of (r1, r2, t): name the part it lives in.
    const Eigen::Matrix<double, 9, 1> weak = svd.matrixV().col(8);
    std::ostringstream message;
    message.precision(2);
    message << std::fixed << what << ": the scan lines do not fix the 2D laser's pose (smallest/largest singular value "
            << std::scientific << singular[8] / singular[0] << std::fixed << "): ";
    if (weak.tail<3>().norm() > weak.head<6>().norm()) {
      const Eigen::Vector3d t = weak.tail<3>().normalized();
      message << "translation along [" << t.x() << " " << t.y() << " " << t.z() << "]";
    } else {
      message << "its orientation";
    }
    message << " is unconstrained; tilt and turn the target more between poses";
    throw InputError(message.str());
  }
  const Eigen::VectorXd x = svd.solve(rhs);
  Eigen::Matrix<double, 3, 2> columns;
  columns << x.segment<3>(0), x.segment<3>(3);
  // Nearest matrix with orthonormal columns, then the third column by the cross product.
  const Eigen::JacobiSVD<Eigen::Matrix<double, 3, 2>> polar(columns, Eigen::ComputeFullU | Eigen::ComputeFullV);
  const Eigen::Matrix<double, 3, 2> orthonormal = polar.matrixU().leftCols<2>() * polar.matrixV().transpose();
  Eigen::Isometry3d rig_from_laser = Eigen::Isometry3d::Identity();
  rig_from_laser.linear() << orthonormal.col(0), orthonormal.col(1), orthonormal.col(0).cross(orthonormal.col(1));
  // t again with the rotation fixed: n . t = -d - n . R p.
  Eigen::MatrixXd N(rows, 3);
  Eigen::VectorXd b(rows);
  row = 0;
  for (std::size_t k = 0; k < planes_in_rig.size(); ++k) {
    for (const Eigen::Vector3d& p : scan_points[k]) {
      N.row(row) = planes_in_rig[k].normal.transpose();
      b[row++] = -planes_in_rig[k].offset - planes_in_rig[k].normal.dot(rig_from_laser.linear() * p);
    }
  }
  rig_from_laser.translation() = N.colPivHouseholderQr().solve(b);
  return rig_from_laser;
}

}  // namespace vocal
