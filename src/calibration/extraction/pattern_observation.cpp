#include "vocal/calibration/extraction/pattern_observation.h"

#include <algorithm>
#include <cmath>
#include <string>

#include <Eigen/Dense>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "vocal/calibration/point_statistics.h"
#include "vocal/core/errors.h"
#include "vocal/core/se3.h"

namespace vocal {

std::vector<Eigen::Vector3d> TargetPattern::corners() const {
  std::vector<Eigen::Vector3d> out;
  for (int r = 0; r < rows; ++r)
    for (int c = 0; c < cols; ++c)
      out.emplace_back((c - 0.5 * (cols - 1)) * square_size, (r - 0.5 * (rows - 1)) * square_size, 0.0);
  return out;
}

std::vector<Eigen::Vector2d> detectPattern(const ColorImage& image, const TargetPattern& pattern, const char* what) {
  cv::Mat gray(image.height(), image.width(), CV_8UC1);
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x) gray.at<std::uint8_t>(y, x) = luma8(image(x, y));
  std::vector<cv::Point2f> corners;
  const cv::Size size(pattern.cols, pattern.rows);
  // A plain threshold first (about 5 ms for 640x480, FAST_CHECK rejects board-free images early); the
  // sector-based detector, which copes with uneven light and blur, when that fails (about 60 ms; the
  // adaptive-threshold variant of the first took 600 ms on a partly visible board).
  bool found = cv::findChessboardCorners(gray, size, corners, cv::CALIB_CB_FAST_CHECK);
  if (!found) found = cv::findChessboardCornersSB(gray, size, corners, cv::CALIB_CB_NORMALIZE_IMAGE);
  if (!found) {
    throw InputError(std::string(what) + ": no " + std::to_string(pattern.rows) + "x" + std::to_string(pattern.cols) +
                     " checkerboard (inner corners) found in the image");
  }
  cv::cornerSubPix(gray, corners, cv::Size(5, 5), cv::Size(-1, -1),
                   cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 50, 0.001));
  std::vector<Eigen::Vector2d> out;
  for (const cv::Point2f& c : corners) out.emplace_back(c.x, c.y);
  return out;
}

PatternObservation observePattern(const std::vector<Eigen::Vector2d>& image_corners, const TargetPattern& pattern,
                                  const PinholeCamera& camera, const char* what, const LensDistortion& distortion) {
  const std::vector<Eigen::Vector3d> object = pattern.corners();
  if (image_corners.size() != object.size()) {
    throw InputError(std::string(what) + ": " + std::to_string(image_corners.size()) + " corners detected, the " +
                     std::to_string(pattern.rows) + "x" + std::to_string(pattern.cols) + " pattern has " +
                     std::to_string(object.size()));
  }
  // PnP on the corners as an ideal pinhole camera would have seen them.
  std::vector<cv::Point3d> all_object;
  std::vector<cv::Point2d> all_ideal;
  for (std::size_t i = 0; i < object.size(); ++i) {
    all_object.emplace_back(object[i].x(), object[i].y(), object[i].z());
    const Eigen::Vector2d ideal = distortion.undistort(
        {(image_corners[i].x() - camera.cx) / camera.fx, (image_corners[i].y() - camera.cy) / camera.fy});
    all_ideal.emplace_back(camera.fx * ideal.x() + camera.cx, camera.fy * ideal.y() + camera.cy);
  }
  const cv::Matx33d K(camera.fx, 0, camera.cx, 0, camera.fy, camera.cy, 0, 0, 1);
  cv::Vec3d rvec, tvec;
  const auto solve = [&](const std::vector<bool>& used) {
    std::vector<cv::Point3d> object_points;
    std::vector<cv::Point2d> image_points;
    for (std::size_t i = 0; i < used.size(); ++i)
      if (used[i]) object_points.push_back(all_object[i]), image_points.push_back(all_ideal[i]);
    if (!cv::solvePnP(object_points, image_points, K, cv::noArray(), rvec, tvec, false, cv::SOLVEPNP_IPPE) ||
        !cv::solvePnP(object_points, image_points, K, cv::noArray(), rvec, tvec, true, cv::SOLVEPNP_ITERATIVE)) {
      throw InputError(std::string(what) + ": the pattern's pose could not be estimated from its corners");
    }
  };
  const auto misfits = [&] {  // each corner's pixel error through the lens at the fitted pose
    cv::Matx33d rotation;
    cv::Rodrigues(rvec, rotation);
    std::vector<double> out;
    for (std::size_t i = 0; i < object.size(); ++i) {
      const cv::Vec3d p = rotation * cv::Vec3d(object[i].x(), object[i].y(), object[i].z()) + tvec;
      out.push_back((projectThroughLens(camera, distortion, Eigen::Vector3d(p[0], p[1], p[2])) - image_corners[i]).norm());
    }
    return out;
  };
  std::vector<bool> used(object.size(), true);
  solve(used);
  // A corner the detector put on the wrong edge (a dark square against a dark background: 8 px off on
  // the real office's pose14.jpg, where every other corner of the 20 views fits within 0.8 px) pulls the
  // whole pose; left out where it lies far beyond the others (at most a tenth of them), the rest solved again.
  const std::size_t most_left_out = object.size() / 10;
  for (int round = 0; round < 2; ++round) {
    const std::vector<double> errors = misfits();
    std::vector<double> kept;
    for (std::size_t i = 0; i < errors.size(); ++i)
      if (used[i]) kept.push_back(errors[i]);
    const double threshold = std::max(kMisdetectedCornerPixels, kMisdetectedCornerMedians * median(std::move(kept)));
    std::vector<bool> next = used;
    std::size_t left_out = 0;
    for (std::size_t i = 0; i < errors.size(); ++i) {
      next[i] = next[i] && errors[i] <= threshold;
      left_out += !next[i];
    }
    if (next == used || left_out > most_left_out) break;
    used = next;
    solve(used);
  }
  cv::Matx33d R;
  cv::Rodrigues(rvec, R);
  PatternObservation observation;
  double squared = 0.0;
  std::vector<Eigen::Vector2d> reprojected;  // each corner through the lens at the fitted pose
  int n = 0;  // corners used
  for (std::size_t i = 0; i < object.size(); ++i) {
    const cv::Vec3d p = R * cv::Vec3d(object[i].x(), object[i].y(), object[i].z()) + tvec;
    observation.points.emplace_back(p[0], p[1], p[2]);
    reprojected.push_back(projectThroughLens(camera, distortion, observation.points.back()));
    if (!used[i]) {
      observation.corners_left_out.push_back(static_cast<int>(i));
      continue;
    }
    squared += (reprojected.back() - image_corners[i]).squaredNorm();
    ++n;
  }
  observation.reprojection_rms_px = std::sqrt(squared / n);
  // Pose covariance sigma^2 (J^T J)^-1 with the pose perturbed as R exp([w]x), t + dt: a corner X moves
  // by -R [X]x w + dt in the camera frame.
  Eigen::Matrix3d rotation;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) rotation(r, c) = R(r, c);
  Eigen::Matrix<double, 6, 6> information = Eigen::Matrix<double, 6, 6>::Zero();
  // ... and against the intrinsics' relative change dk (a pixel u = fx xd + cx of the distorted
  // normalised point moves by fx xd dk_fx + fx dk_cx), for the graph's refinement of them.
  Eigen::Matrix<double, 6, 4> pose_by_intrinsics = Eigen::Matrix<double, 6, 4>::Zero();
  Eigen::Matrix4d intrinsics_information = Eigen::Matrix4d::Zero();
  Eigen::Matrix<double, 6, 1> pose_gradient = Eigen::Matrix<double, 6, 1>::Zero();
  Eigen::Vector4d intrinsics_gradient = Eigen::Vector4d::Zero();
  for (std::size_t i = 0; i < object.size(); ++i) {
    if (!used[i]) continue;
    const Eigen::Vector3d& p = observation.points[i];
    // Pixel <- distorted <- normalised <- camera point: the noise is the detected (distorted) pixels'.
    Eigen::Matrix<double, 2, 3> normalisation;
    normalisation << 1.0 / p.z(), 0.0, -p.x() / (p.z() * p.z()),  //
        0.0, 1.0 / p.z(), -p.y() / (p.z() * p.z());
    const Eigen::Matrix<double, 2, 3> projection = Eigen::Vector2d(camera.fx, camera.fy).asDiagonal() *
                                                   distortion.jacobian({p.x() / p.z(), p.y() / p.z()}) * normalisation;
    Eigen::Matrix<double, 3, 6> motion;
    motion.leftCols<3>() = -rotation * skew(object[i]);
    motion.rightCols<3>() = Eigen::Matrix3d::Identity();
    const Eigen::Matrix<double, 2, 6> J = projection * motion;
    information += J.transpose() * J;
    const Eigen::Vector2d& pixel = reprojected[i];
    Eigen::Matrix<double, 2, 4> by_intrinsics;
    by_intrinsics << pixel.x() - camera.cx, 0.0, camera.fx, 0.0,  //
        0.0, pixel.y() - camera.cy, 0.0, camera.fy;
    const Eigen::Vector2d misfit = pixel - image_corners[i];
    pose_by_intrinsics += J.transpose() * by_intrinsics;
    intrinsics_information += by_intrinsics.transpose() * by_intrinsics;
    pose_gradient += J.transpose() * misfit;
    intrinsics_gradient += by_intrinsics.transpose() * misfit;
  }
  // Per image axis: 2n residuals less the pose's 6 degrees of freedom.
  const double pixel_sigma = std::max(0.05, std::sqrt(squared / std::max(2.0 * n - 6.0, 1.0)));
  const Eigen::Matrix<double, 6, 6> pose_covariance = pixel_sigma * pixel_sigma * information.inverse();
  // The plane's (tilt x, tilt y, centre distance): the normal R exp([w]x) e_z has components -w_y and
  // w_x along the pattern's x and y axes; the centre t moves by n . dt along the normal.
  const Eigen::Vector3d normal = rotation.col(2);
  Eigen::Matrix<double, 3, 6> to_plane = Eigen::Matrix<double, 3, 6>::Zero();
  to_plane(0, 1) = -1.0;
  to_plane(1, 0) = 1.0;
  to_plane.block<1, 3>(2, 3) = normal.transpose();
  observation.plane.sensor_from_pattern.linear() = rotation;
  observation.plane.sensor_from_pattern.translation() = Eigen::Vector3d(tvec[0], tvec[1], tvec[2]);
  observation.plane.covariance = to_plane * pose_covariance * to_plane.transpose();
  observation.plane.pose_covariance = pose_covariance;
  // The pose's best response to dk (the PnP solved again: -A^-1 B dk), and what is left of the corners'
  // misfit once the pose has responded (the Schur complement), whitened by the pixel noise.
  const Eigen::LDLT<Eigen::Matrix<double, 6, 6>> pose_solve(information);
  observation.plane.intrinsics = Eigen::Vector4d(camera.fx, camera.fy, camera.cx, camera.cy);
  observation.plane.pose_per_intrinsics = -pose_solve.solve(pose_by_intrinsics);
  const Eigen::Matrix4d left = (intrinsics_information + pose_by_intrinsics.transpose() * observation.plane.pose_per_intrinsics) /
                               (pixel_sigma * pixel_sigma);
  const Eigen::Vector4d gradient = (intrinsics_gradient - pose_by_intrinsics.transpose() * pose_solve.solve(pose_gradient)) /
                                   (pixel_sigma * pixel_sigma);
  // |L dk + b|^2 = dk^T left dk + 2 gradient^T dk + constant, over the directions the view fixes.
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d> eigen(0.5 * (left + left.transpose()));
  for (int k = 0; k < 4; ++k) {
    const double lambda = eigen.eigenvalues()[k];
    if (!(lambda > 1e-9 * std::max(1.0, eigen.eigenvalues()[3]))) continue;
    const Eigen::Vector4d v = eigen.eigenvectors().col(k);
    observation.plane.evidence_matrix.row(k) = std::sqrt(lambda) * v.transpose();
    observation.plane.evidence_offset[k] = v.dot(gradient) / std::sqrt(lambda);
  }
  return observation;
}

}  // namespace vocal
