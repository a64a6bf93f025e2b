#include "vocal/calibration/pattern_observation.h"

#include <algorithm>
#include <cmath>
#include <string>

#include <Eigen/Dense>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "vocal/core/errors.h"

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
  for (int y = 0; y < image.height(); ++y) {
    for (int x = 0; x < image.width(); ++x) {
      const Rgb8& p = image(x, y);
      gray.at<std::uint8_t>(y, x) = static_cast<std::uint8_t>((299 * p.r + 587 * p.g + 114 * p.b) / 1000);
    }
  }
  std::vector<cv::Point2f> corners;
  const cv::Size size(pattern.cols, pattern.rows);
  if (!cv::findChessboardCorners(gray, size, corners, cv::CALIB_CB_ADAPTIVE_THRESH | cv::CALIB_CB_NORMALIZE_IMAGE)) {
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
                                  const PinholeCamera& camera, const char* what) {
  const std::vector<Eigen::Vector3d> object = pattern.corners();
  if (image_corners.size() != object.size()) {
    throw InputError(std::string(what) + ": " + std::to_string(image_corners.size()) + " corners detected, the " +
                     std::to_string(pattern.rows) + "x" + std::to_string(pattern.cols) + " pattern has " +
                     std::to_string(object.size()));
  }
  std::vector<cv::Point3d> object_points;
  std::vector<cv::Point2d> image_points;
  for (std::size_t i = 0; i < object.size(); ++i) {
    object_points.emplace_back(object[i].x(), object[i].y(), object[i].z());
    image_points.emplace_back(image_corners[i].x(), image_corners[i].y());
  }
  const cv::Matx33d K(camera.fx, 0, camera.cx, 0, camera.fy, camera.cy, 0, 0, 1);
  cv::Vec3d rvec, tvec;
  if (!cv::solvePnP(object_points, image_points, K, cv::noArray(), rvec, tvec, false, cv::SOLVEPNP_IPPE) ||
      !cv::solvePnP(object_points, image_points, K, cv::noArray(), rvec, tvec, true, cv::SOLVEPNP_ITERATIVE)) {
    throw InputError(std::string(what) + ": the pattern's pose could not be estimated from its corners");
  }
  cv::Matx33d R;
  cv::Rodrigues(rvec, R);
  PatternObservation observation;
  double squared = 0.0;
  for (std::size_t i = 0; i < object.size(); ++i) {
    const cv::Vec3d p = R * cv::Vec3d(object[i].x(), object[i].y(), object[i].z()) + tvec;
    observation.points.emplace_back(p[0], p[1], p[2]);
    const Eigen::Vector2d projected = camera.project(observation.points.back());
    squared += (projected - image_corners[i]).squaredNorm();
  }
  observation.reprojection_rms_px = std::sqrt(squared / object.size());
  // Pose covariance sigma^2 (J^T J)^-1 from the reprojection Jacobian; the plane offset d = -n . t
  // varies with t along n.
  std::vector<cv::Point2d> projected;
  cv::Mat jacobian;
  cv::projectPoints(object_points, rvec, tvec, K, cv::noArray(), projected, jacobian);
  const int n = static_cast<int>(object.size());
  Eigen::MatrixXd J(2 * n, 6);
  for (int r = 0; r < 2 * n; ++r)
    for (int c = 0; c < 6; ++c) J(r, c) = jacobian.at<double>(r, c);
  const double pixel_sigma =
      std::max(0.05, observation.reprojection_rms_px * std::sqrt(2.0 * n / std::max(2.0 * n - 6.0, 1.0)));
  const Eigen::Matrix<double, 6, 6> covariance = pixel_sigma * pixel_sigma * (J.transpose() * J).inverse();
  const Eigen::Vector3d normal(R(0, 2), R(1, 2), R(2, 2));
  observation.offset_sigma = std::sqrt(normal.dot(covariance.bottomRightCorner<3, 3>() * normal));
  return observation;
}

}  // namespace vocal
