#include "vocal/calibration/solver/pairwise_initialization.h"

#include <limits>
#include <sstream>

#include <Eigen/SVD>

#include "vocal/core/errors.h"

namespace vocal {

Eigen::Isometry3d alignPlanes(const std::vector<Plane>& in_a, const std::vector<Plane>& in_b, const std::string& what,
                              const BoardCentres* centres) {
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
  if (centres && singular[1] < 0.05 * singular[0]) {
    throw InputError(what + ": the target planes are all nearly parallel: even their board centres leave the rotation free; "
                     "tilt the target more between poses");
  }
  if (!centres && singular[2] < 0.05 * singular[0]) {
    std::ostringstream message;
    message.precision(3);
    const Eigen::Vector3d weak = spread.matrixV().col(2);
    message << what << ": the target planes are too close to parallel (normal spread " << singular[2] / singular[0]
            << " < 0.05): translation along [" << weak.x() << " " << weak.y() << " " << weak.z()
            << "] is unconstrained; tilt the target more between poses, or calibrate with the board's edges as well (calibrate_rig's "
               "and the nodelet's default: leave out --no-edges, set board_edges true)";
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
  if (!centres) {
    a_from_b.translation() = normals_a.colPivHouseholderQr().solve(offsets);
    return a_from_b;
  }
  if (centres->in_a.size() != in_a.size() || centres->in_b.size() != in_a.size()) {
    throw InputError(what + ": " + std::to_string(centres->in_a.size()) + " and " + std::to_string(centres->in_b.size()) +
                     " board centres for " + std::to_string(n) + " planes");
  }
  // Offsets, then t = c_a - R c_b per centre, less weighted.
  Eigen::MatrixXd A(n + 3 * n, 3);
  Eigen::VectorXd b(n + 3 * n);
  A.topRows(n) = normals_a;
  b.head(n) = offsets;
  for (int i = 0; i < n; ++i) {
    A.block<3, 3>(n + 3 * i, 0) = centres->weight * Eigen::Matrix3d::Identity();
    b.segment<3>(n + 3 * i) = centres->weight * (centres->in_a[i] - a_from_b.linear() * centres->in_b[i]);
  }
  a_from_b.translation() = A.colPivHouseholderQr().solve(b);
  return a_from_b;
}

Eigen::Isometry3d alignLaserLines(const std::vector<Plane>& planes_in_rig,
                                  const std::vector<std::vector<Eigen::Vector3d>>& scan_points, const std::string& what,
                                  const ScanEnds* scan_ends) {
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
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(M, Eigen::ComputeThinU | Eigen::ComputeThinV);
  Eigen::VectorXd singular = svd.singularValues();
  // Where the boards' normals leave a direction w nearly free (a board tilted only up and down), the
  // planes say little along the lines. A scan crossing the board between opposite edges (across its
  // axis a, the one nearest w, signed along w) has its midpoint m on the board's centre line,
  // a . (R m + t) = a . c, and its chord d = e2 - e1 spans the board's side L along a: a . R d = s L,
  // with one sign s for every scan (the beam order runs one way along w); both signs are solved and
  // the one that fits better kept.
  struct EdgeRow {
    Eigen::Vector3d axis, midpoint, chord;
    double at, side;
  };
  std::vector<EdgeRow> edge_rows;
  if (scan_ends) {
    Eigen::MatrixXd normals(planes_in_rig.size(), 3);
    for (std::size_t k = 0; k < planes_in_rig.size(); ++k) normals.row(k) = planes_in_rig[k].normal.transpose();
    const Eigen::JacobiSVD<Eigen::MatrixXd> spread(normals, Eigen::ComputeFullV);
    if (spread.singularValues()[2] < scan_ends->weak_spread * spread.singularValues()[0]) {
      const Eigen::Vector3d free = spread.matrixV().col(2);
      for (std::size_t k = 0; k < scan_ends->ends.size() && k < scan_ends->rig_from_board.size(); ++k) {
        if (scan_ends->ends[k].size() != 2) continue;
        const Eigen::Isometry3d& board = scan_ends->rig_from_board[k];
        const Eigen::Vector3d x = board.linear().col(0), y = board.linear().col(1);
        const bool along_x = std::abs(x.dot(free)) >= std::abs(y.dot(free));
        Eigen::Vector3d axis = along_x ? x : y;
        if (axis.dot(free) < 0.0) axis = -axis;
        edge_rows.push_back({axis, 0.5 * (scan_ends->ends[k][0] + scan_ends->ends[k][1]), scan_ends->ends[k][1] - scan_ends->ends[k][0],
                             axis.dot(board.translation()), along_x ? scan_ends->board_width : scan_ends->board_height});
      }
    }
  }
  if (!edge_rows.empty()) {
    const std::size_t extra = 2 * edge_rows.size();
    Eigen::MatrixXd best_M;
    Eigen::VectorXd best_rhs;
    double best_error = std::numeric_limits<double>::infinity();
    for (double sign : {1.0, -1.0}) {
      Eigen::MatrixXd A(rows + extra, 9);
      Eigen::VectorXd y(rows + extra);
      A.topRows(rows) = M.topRows(rows);
      y.head(rows) = rhs.head(rows);
      for (std::size_t i = 0; i < edge_rows.size(); ++i) {
        const EdgeRow& e = edge_rows[i];
        A.row(rows + 2 * i) << e.midpoint.x() * e.axis.transpose(), e.midpoint.y() * e.axis.transpose(), e.axis.transpose();
        y[rows + 2 * i] = e.at;
        A.row(rows + 2 * i + 1) << e.chord.x() * e.axis.transpose(), e.chord.y() * e.axis.transpose(), Eigen::RowVector3d::Zero();
        y[rows + 2 * i + 1] = sign * e.side;
      }
      A.bottomRows(extra) *= scan_ends->weight;
      y.tail(extra) *= scan_ends->weight;
      const Eigen::VectorXd solution = A.colPivHouseholderQr().solve(y);
      const double error = (A * solution - y).squaredNorm();
      if (error < best_error) best_error = error, best_M = A, best_rhs = y;
    }
    M = best_M;
    rhs = best_rhs;
    svd.compute(M, Eigen::ComputeThinU | Eigen::ComputeThinV);
    singular = svd.singularValues();
  }
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
  Eigen::MatrixXd N(rows + edge_rows.size(), 3);
  Eigen::VectorXd b(rows + edge_rows.size());
  row = 0;
  for (std::size_t k = 0; k < planes_in_rig.size(); ++k) {
    for (const Eigen::Vector3d& p : scan_points[k]) {
      N.row(row) = planes_in_rig[k].normal.transpose();
      b[row++] = -planes_in_rig[k].offset - planes_in_rig[k].normal.dot(rig_from_laser.linear() * p);
    }
  }
  for (const EdgeRow& e : edge_rows) {  // the midpoints on the centre lines
    N.row(row) = scan_ends->weight * e.axis.transpose();
    b[row++] = scan_ends->weight * (e.at - e.axis.dot(rig_from_laser.linear() * e.midpoint));
  }
  rig_from_laser.translation() = N.colPivHouseholderQr().solve(b);
  return rig_from_laser;
}

}  // namespace vocal
