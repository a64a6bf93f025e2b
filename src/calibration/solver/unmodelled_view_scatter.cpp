#include "vocal/calibration/solver/unmodelled_view_scatter.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Cholesky>

#include "vocal/calibration/solver/misdetected_view.h"
#include "vocal/core/se3.h"

namespace vocal {

Eigen::Matrix<double, 6, 1> viewPoseError(const PlaneMeasurement& view, const Eigen::Isometry3d& predicted) {
  const Eigen::AngleAxisd turn(view.sensor_from_pattern.linear().transpose() * predicted.linear());
  Eigen::Matrix<double, 6, 1> error;
  error.head<3>() = turn.angle() * turn.axis();
  error.tail<3>() = predicted.translation() - view.sensor_from_pattern.translation();
  return error;
}

namespace {
double median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}
}  // namespace

void ViewScatterSamples::add(const Eigen::Matrix<double, 6, 1>& mean_error, Eigen::Matrix<double, 6, 6> covariance, double rotation_sigma,
                             double translation_sigma, double lever) {
  covariance.topLeftCorner<3, 3>() += rotation_sigma * rotation_sigma * Eigen::Matrix3d::Identity();
  covariance.bottomRightCorner<3, 3>() += (std::pow(translation_sigma, 2) + std::pow(rotation_sigma * lever, 2)) * Eigen::Matrix3d::Identity();
  chi2_.push_back(mean_error.dot(covariance.ldlt().solve(mean_error)));
  rotation_.push_back(mean_error.head<3>().squaredNorm() / 3.0);
  translation_.push_back(mean_error.tail<3>().squaredNorm() / 3.0);
}

ViewScatter ViewScatterSamples::scatter() const {
  constexpr double kChiSquareMedian6 = 5.35;
  if (chi2_.empty() || median(chi2_) <= 2.0 * kChiSquareMedian6) return {};
  // Each sample is the mean of 3 squared normals (one per axis): its median is 0.789 of its mean (chi-square
  // with 3 degrees of freedom: 2.366 / 3), not a single squared normal's 0.455, which read it 32 % high.
  constexpr double kMedianOfChiSquare3Over3 = 0.789;
  return {std::sqrt(median(rotation_) / kMedianOfChiSquare3Over3), std::sqrt(median(translation_) / kMedianOfChiSquare3Over3)};
}

ViewScatter unmodelledViewScatter(const std::vector<SensorSpec>& sensors, const std::vector<TargetObservation>& observations,
                                  const CalibrationResult& solved) {
  const JointedMounts& mounts = solved.mounts;
  ViewScatterSamples samples;
  const Eigen::Isometry3d print = Eigen::Translation3d(solved.print_on_board.x(), solved.print_on_board.y(), 0.0) *
                                  Eigen::AngleAxisd(solved.print_on_board.z(), Eigen::Vector3d::UnitZ());
  for (const TargetObservation& o : observations) {
    if (o.plane_measurements.empty() || sensors.at(o.sensor).type != SensorType::kCamera) continue;
    if (!solved.board_mount || solved.sensors.at(o.sensor).isolated) continue;
    // Both where the arm put them (the reported tool, the joints' readings with the offsets as solved), not
    // the still pose's blocks, which the views pull within the arm's repeatability and beyond.
    const Eigen::Isometry3d board = mounts.boardFrameAt(o.target_pose) * *solved.board_mount;
    const Eigen::Isometry3d predicted = solved.rigFromSensorAt(o).inverse() * board * print;
    Eigen::Matrix<double, 6, 1> mean = Eigen::Matrix<double, 6, 1>::Zero();
    Eigen::Matrix<double, 6, 6> covariance = Eigen::Matrix<double, 6, 6>::Zero();
    int n = 0;
    for (const PlaneMeasurement& found : o.plane_measurements) {
      const bool reversed = rotationAngle(found.sensor_from_pattern.inverse() * predicted) > 0.5 * M_PI;
      const PlaneMeasurement view = reversed ? turnedHalfway(found) : found;
      const Eigen::Matrix<double, 6, 1> error = viewPoseError(view, predicted);
      // Held by its plane only in the solve (misdetected_view.h): not the scatter of the views it weighs.
      if (error.tail<3>().norm() > kMisdetectedViewDistance || error.head<3>().norm() > kMisdetectedViewAngle) continue;
      mean += error;
      covariance += view.pose_covariance;
      ++n;
    }
    if (n == 0) continue;
    mean /= n;
    covariance /= static_cast<double>(n) * n;  // of the mean of n independent views
    // The tool's turn moves the board seen by its lever: from the camera's frame to the board, or to the board on the tool.
    const double lever = mounts.moves(o.sensor) ? solved.sensors[o.sensor].reference_from_sensor.translation().norm() + predicted.translation().norm()
                                                : solved.board_mount->translation().norm();
    samples.add(mean, covariance, mounts.tool_rotation_sigma, mounts.tool_translation_sigma, lever);
  }
  return samples.scatter();
}

std::vector<TargetObservation> withViewScatter(std::vector<TargetObservation> observations, const std::vector<SensorSpec>& sensors,
                                               const ViewScatter& scatter) {
  for (TargetObservation& o : observations) {
    if (sensors.at(o.sensor).type != SensorType::kCamera) continue;
    const double shared = static_cast<double>(o.plane_measurements.size());
    for (PlaneMeasurement& view : o.plane_measurements) {
      view.pose_covariance.topLeftCorner<3, 3>() += shared * scatter.rotation * scatter.rotation * Eigen::Matrix3d::Identity();
      view.pose_covariance.bottomRightCorner<3, 3>() += shared * scatter.translation * scatter.translation * Eigen::Matrix3d::Identity();
    }
  }
  return observations;
}

}  // namespace vocal
