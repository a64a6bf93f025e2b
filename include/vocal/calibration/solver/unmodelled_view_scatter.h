#pragma once
// What cameras' whole-pose views of the board (BoardEdgeOptions::camera_pose) disagree by beyond their PnP
// covariance and the arm's repeatability, as the arm's graph measures it (HandEyeResult::unmodelled_*): a
// real arm's kinematic model, a real camera's intrinsics and the print are off by millimetres, far beyond
// either, and alike for every image of one still pose. Held at the PnP covariance alone, the views pull
// the graph where one pose's shared error puts it (the real Franka: 8 mm / 18 mrad between re-solves
// without one pose); weighted by it, as the arm's graph weights them.

#include <vector>

#include <Eigen/Core>

#include "vocal/calibration/calibration_types.h"
#include "vocal/calibration/solver/graph_calibration.h"

namespace vocal {

// A camera view's error against the pose the unknowns predict (camera <- pattern), as CameraViewResidual
// takes it unwhitened: (w, dt) of the view's perturbation R exp([w]x), t + dt.
Eigen::Matrix<double, 6, 1> viewPoseError(const PlaneMeasurement& view, const Eigen::Isometry3d& predicted);

// Per still pose and camera, the mean of its views' errors (w, dt) against the solution and their modelled
// covariance (the views' PnP covariance over their count): with the arm's repeatability (`rotation_sigma`,
// `translation_sigma`, its turn moving the board seen by `lever` metres) added, the scatter beyond them
// over all still poses. Where the median pose's chi-square is over twice what 6 degrees of freedom give
// (5.35), the still poses' median squared mean error per axis; zero otherwise (the median: one poor pose
// does not raise it). Both graphs' (the arm's unmodelledScatter).
class ViewScatterSamples {
 public:
  void add(const Eigen::Matrix<double, 6, 1>& mean_error, Eigen::Matrix<double, 6, 6> covariance, double rotation_sigma, double translation_sigma,
           double lever);
  ViewScatter scatter() const;

 private:
  std::vector<double> chi2_, rotation_, translation_;
};

// ViewScatterSamples over `solved`'s whole-pose camera views: each against the board and the camera where
// the arm put them (the reported tool, or the readings with the offsets as solved) and the print's place,
// the arm's repeatability `solved.mounts` gives.
ViewScatter unmodelledViewScatter(const std::vector<SensorSpec>& sensors, const std::vector<TargetObservation>& observations,
                                  const CalibrationResult& solved);

// `observations` with each camera view's pose covariance widened by `scatter`, times its still pose's view
// count (the views of one pose share that error: together they weigh as one view would).
std::vector<TargetObservation> withViewScatter(std::vector<TargetObservation> observations, const std::vector<SensorSpec>& sensors,
                                               const ViewScatter& scatter);

}  // namespace vocal
