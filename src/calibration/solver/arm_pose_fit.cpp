#include "vocal/calibration/solver/arm_pose_fit.h"

#include <algorithm>
#include <cmath>

#include "vocal/calibration/solver/unmodelled_view_scatter.h"
#include "vocal/core/se3.h"

namespace vocal {

namespace {
// `frame` as solved against `arm`, where the arm put it; from the reported tool (`from_tool`), the departure
// in its sigmas (from the joints the readings' corrections give it).
void compareWithTool(const Eigen::Isometry3d& frame, const Eigen::Isometry3d& arm, const JointedMounts& mounts, bool from_tool, ArmPoseFit* fit) {
  const double shift = (frame.translation() - arm.translation()).norm(), turn = rotationAngle(arm.inverse() * frame);
  if (shift >= fit->shift) fit->shift = shift, fit->turn = turn;
  if (from_tool) fit->departure = std::max({fit->departure, shift / mounts.tool_translation_sigma, turn / mounts.tool_rotation_sigma});
}
}  // namespace

std::map<int, ArmPoseFit> armPoseFits(const std::vector<SensorSpec>& sensors, const std::vector<TargetObservation>& observations,
                                      const CalibrationResult& solved) {
  const JointedMounts& mounts = solved.mounts;
  std::map<int, ArmPoseFit> fits;
  bool any_moves = mounts.boardMoves();
  for (std::size_t s = 0; s < sensors.size(); ++s) any_moves = any_moves || mounts.moves(static_cast<int>(s));
  if (!any_moves) return fits;
  for (const TargetObservation& o : observations) fits[o.target_pose];
  // The board on the arm (or lying still in its base): its block per pose against the arm's tool (the base).
  if (solved.board_mount) {
    for (auto& [k, fit] : fits) {
      const auto board = solved.boards.find(k);
      if (board == solved.boards.end()) continue;
      const bool from_tool = mounts.board_chain.empty();
      compareWithTool(board->second, mounts.boardFrameAt(k) * *solved.board_mount, mounts, from_tool, &fit);
    }
  }
  // The sensors the arm carries: where the still pose's block put each against its mount frame there.
  std::map<std::pair<int, int>, const TargetObservation*> observation_of;  // (sensor, still pose)
  for (const TargetObservation& o : observations) observation_of[{o.sensor, o.target_pose}] = &o;
  for (const auto& [key, placed] : solved.placed_at_poses) {
    const auto o = observation_of.find(key);
    if (o == observation_of.end()) continue;
    compareWithTool(placed, solved.rigFromSensorAt(*o->second), mounts, mounts.onReportedTool(key.first), &fits[key.second]);
  }
  // From the joints: how far each reading had to move, in its sigma.
  for (const auto& [key, correction] : solved.reading_corrections) {
    const auto [k, j] = key;
    if (!fits.count(k)) continue;
    fits[k].departure = std::max(fits[k].departure, std::abs(correction) / mounts.tolerances.readingSigma(mounts.joints.at(j)));
  }
  const Eigen::Isometry3d print = Eigen::Translation3d(solved.print_on_board.x(), solved.print_on_board.y(), 0.0) *
                                  Eigen::AngleAxisd(solved.print_on_board.z(), Eigen::Vector3d::UnitZ());
  for (const TargetObservation& o : observations) {
    if (o.plane_measurements.empty() || sensors.at(o.sensor).type != SensorType::kCamera || !solved.board_mount) continue;
    ArmPoseFit& fit = fits[o.target_pose];
    const Eigen::Isometry3d predicted = solved.rigFromSensorAt(o).inverse() * mounts.boardFrameAt(o.target_pose) * *solved.board_mount * print;
    for (const PlaneMeasurement& found : o.plane_measurements) {
      const bool reversed = rotationAngle(found.sensor_from_pattern.inverse() * predicted) > 0.5 * M_PI;
      const Eigen::Matrix<double, 6, 1> error = viewPoseError(reversed ? turnedHalfway(found) : found, predicted);
      fit.view_distance += error.tail<3>().norm();
      fit.view_angle += error.head<3>().norm();
      ++fit.views;
    }
  }
  for (auto& [k, fit] : fits) {
    fit.poor = fit.departure > mounts.tool_loss_sigmas;
    if (fit.views > 0) fit.view_distance /= fit.views, fit.view_angle /= fit.views;
  }
  return fits;
}

}  // namespace vocal
