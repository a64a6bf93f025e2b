// The still-pose graph's residual kinds (calibration/solver/*.h used by graph_calibration.cpp), each on
// its own: zero where the unknowns agree with the observation, and the observation's error in its standard
// deviations where they are off by a known amount.
#include <gtest/gtest.h>

#include "graph_residual_support.h"

#include <cmath>
#include <cstdint>
#include <memory>
#include <random>
#include <vector>

#include <Eigen/Geometry>
#include <ceres/cost_function.h>

#include "vocal/calibration/joint_chain.h"
#include "vocal/calibration/solver/beam_range_residual.h"
#include "vocal/calibration/solver/camera_outline_residual.h"
#include "vocal/calibration/solver/camera_pose_on_board_residual.h"
#include "vocal/calibration/solver/on_board_plane.h"
#include "vocal/calibration/solver/outline_points_residual.h"
#include "vocal/calibration/solver/plane_measurement_residual.h"
#include "vocal/calibration/solver/point_plane_residual.h"
#include "vocal/calibration/solver/unmodelled_view_scatter.h"
#include "vocal/calibration/solver/link_from_joints_cost.h"
#include "vocal/calibration/solver/weak_board_prior.h"
#include "vocal/core/se3.h"

namespace {
using vocal_test::Blocks;
using vocal_test::pose;

// A camera in the rig frame and a board (rig <- board) in front of it, and the camera's view of the board.
struct Scene {
  Eigen::Isometry3d camera = pose({0.05, -0.02, 0.1}, 0.3, {1, 2, 3});
  Eigen::Isometry3d board = camera * pose({0.1, -0.05, 1.2}, 0.4, {1, -1, 0.2});
  vocal::PlaneMeasurement view() const {
    vocal::PlaneMeasurement m;
    m.sensor_from_pattern = camera.inverse() * board;
    return m;
  }
};

// Evaluates a 4-block plane residual (sensor q, t, plane normal, offset) at a plane of the rig frame.
template <typename Residual, int kSize>
Eigen::Matrix<double, kSize, 1> onPlane(const Residual& residual, const Eigen::Isometry3d& sensor, const Eigen::Isometry3d& board) {
  const Blocks x(sensor);
  const Eigen::Vector3d normal = board.linear().col(2);
  const double offset = -normal.dot(board.translation());
  Eigen::Matrix<double, kSize, 1> r;
  residual(x.q.coeffs().data(), x.t.data(), normal.data(), &offset, r.data());
  return r;
}
}  // namespace

// A camera's plane measurement: zero on the board's plane; the plane 10 mm further along its normal with a
// 2 mm sigma on the centre's distance is 5 sigmas there alone; the board tilted by 3 mrad about the
// pattern's x with 1 mrad sigmas is 3 of them on the tilt about y (the normal leaning along y).
TEST(RigGraphResiduals, PlaneMeasurementIsThePatternsTiltAndDistanceInTheirSigmas) {
  const Scene scene;
  vocal::PlaneMeasurement view = scene.view();
  view.covariance = Eigen::Vector3d(1e-6, 1e-6, 4e-6).asDiagonal();
  const vocal::PlaneMeasurementResidual residual(view);
  EXPECT_LT((onPlane<vocal::PlaneMeasurementResidual, 3>(residual, scene.camera, scene.board)).norm(), 1e-9);

  const Eigen::Isometry3d further = Eigen::Translation3d(0.01 * scene.board.linear().col(2)) * scene.board;
  const Eigen::Vector3d shifted = onPlane<vocal::PlaneMeasurementResidual, 3>(residual, scene.camera, further);
  EXPECT_NEAR(std::abs(shifted[2]), 5.0, 1e-6);
  EXPECT_LT(shifted.head<2>().norm(), 1e-9);

  const Eigen::Isometry3d tilted = scene.board * pose(Eigen::Vector3d::Zero(), 3e-3, {1, 0, 0});
  const Eigen::Vector3d turned = onPlane<vocal::PlaneMeasurementResidual, 3>(residual, scene.camera, tilted);
  EXPECT_NEAR(std::abs(turned[1]), 3.0, 1e-3);
  EXPECT_LT(std::abs(turned[0]) + std::abs(turned[2]), 1e-6);
}

// With no intrinsics correction the fifth block changes nothing; a correction moves the view as
// pose_per_intrinsics says: a focal length 1 % longer that moves the pattern 5 mm further (along the
// camera's z, here the board's normal) is 5 mm off the board's plane.
TEST(RigGraphResiduals, PlaneMeasurementWithIntrinsicsMovesTheViewByItsResponse) {
  Scene scene;
  scene.board = scene.camera * pose({0.0, 0.0, 1.0}, 0.0, {1, 0, 0});  // the board square to the camera
  vocal::PlaneMeasurement view = scene.view();
  view.covariance = Eigen::Matrix3d::Identity() * 1e-6;
  view.pose_per_intrinsics(5, 0) = 0.5;  // dt_z per dfx / fx
  const vocal::PlaneMeasurementWithIntrinsics with{vocal::PlaneMeasurementResidual(view)};
  const Blocks x(scene.camera);
  const Eigen::Vector3d normal = scene.board.linear().col(2);
  const double offset = -normal.dot(scene.board.translation());
  for (const double dfx : {0.0, 0.01}) {
    const Eigen::Vector4d dk(dfx, 0.0, 0.0, 0.0);
    Eigen::Vector3d r;
    with(x.q.coeffs().data(), x.t.data(), normal.data(), &offset, dk.data(), r.data());
    EXPECT_NEAR(std::abs(r[2]), dfx * 0.5 / 1e-3, 1e-6);
    EXPECT_LT(r.head<2>().norm(), 1e-9);
  }
}

// A plane residual on a board pose is the same residual on the board's z = 0 plane, for a camera's view
// and for a range sensor's points.
TEST(RigGraphResiduals, OnBoardPlaneIsThePlaneResidualOnTheBoardsPlane) {
  const Scene scene;
  vocal::PlaneMeasurement view = scene.view();
  view.covariance = Eigen::Vector3d(1e-6, 2e-6, 4e-6).asDiagonal();
  const Eigen::Isometry3d board = Eigen::Translation3d(0.004, -0.002, 0.007) * scene.board * pose(Eigen::Vector3d::Zero(), 0.01, {1, 1, 0});
  const Blocks x(scene.camera), b(board);

  const vocal::PlaneMeasurementResidual plane(view);
  Eigen::Vector3d on_board;
  vocal::OnBoardPlane<vocal::PlaneMeasurementResidual>{plane}(x.q.coeffs().data(), x.t.data(), b.q.coeffs().data(), b.t.data(), on_board.data());
  EXPECT_LT((on_board - onPlane<vocal::PlaneMeasurementResidual, 3>(plane, scene.camera, board)).norm(), 1e-9);
  EXPECT_GT(on_board.norm(), 1.0);  // the moved board is seen as moved

  std::vector<Eigen::Vector3d> points;
  for (double u = -0.2; u <= 0.2; u += 0.1)
    for (double v = -0.15; v <= 0.15; v += 0.1) points.push_back(view.sensor_from_pattern * Eigen::Vector3d(u, v, 0.0));
  const vocal::ObservationOnPlaneResidual range(points, 0.005);
  Eigen::Vector4d range_on_board;
  vocal::OnBoardPlane<vocal::ObservationOnPlaneResidual>{range}(x.q.coeffs().data(), x.t.data(), b.q.coeffs().data(), b.t.data(),
                                                               range_on_board.data());
  EXPECT_LT((range_on_board - onPlane<vocal::ObservationOnPlaneResidual, 4>(range, scene.camera, board)).norm(), 1e-9);
}

// A 2D laser's scan as range errors along its beams: zero on the plane; the plane 20 mm further along a
// normal facing the laser leaves each beam 2 standard deviations of 10 mm over the cosine of its
// incidence short, whichever way the plane's normal points.
TEST(RigGraphResiduals, BeamRangeIsEachBeamsRangeErrorToThePlane) {
  const Eigen::Isometry3d laser = pose({0.1, 0.2, 0.3}, 0.5, {0, 0, 1});
  std::vector<Eigen::Vector3d> points;  // the scan (laser frame) on the plane x = 1 m of the laser's frame
  for (const double y : {-0.3, 0.0, 0.2}) points.push_back({1.0, y, 0.0});
  const vocal::BeamRangePlaneResidual residual{points, 0.01};
  for (const double shift : {0.0, 0.02}) {
    for (const double side : {1.0, -1.0}) {
      const Eigen::Vector3d normal = side * (laser.linear() * Eigen::Vector3d::UnitX());
      const Eigen::Vector3d on_plane = laser * Eigen::Vector3d(1.0 + shift, 0.0, 0.0);
      const double offset = -normal.dot(on_plane);
      const Blocks x(laser);
      double r[3];
      residual(x.q.coeffs().data(), x.t.data(), normal.data(), &offset, r);
      for (std::size_t i = 0; i < points.size(); ++i) EXPECT_NEAR(r[i], -shift / 0.01 * points[i].norm(), 1e-9) << i << " " << side;
    }
  }
}

// The outline a camera's pattern predicts: zero on the board's edges; the board 10 mm to the side of
// where the view puts it, 2 standard deviations of 5 mm for the points that shift moves off the outline.
TEST(RigGraphResiduals, CameraOutlineIsThePredictedEdgesDistanceToTheBoards) {
  const Scene scene;
  const vocal::PlaneMeasurement view = scene.view();
  const double width = 0.6, height = 0.45;
  const Eigen::Vector4d no_correction = Eigen::Vector4d::Zero();
  const Blocks x(scene.camera);
  for (const double shift : {0.0, 0.01}) {
    const Blocks b(scene.board * Eigen::Translation3d(shift, 0.0, 0.0));
    for (const Eigen::Vector3d& on_pattern : vocal::patternOutline(width, height)) {
      const vocal::CameraOutlineWithIntrinsics residual{on_pattern, view.sensor_from_pattern, view.pose_per_intrinsics, 0.005, 0.5 * width,
                                                        0.5 * height};
      double r = 0.0;
      residual(x.q.coeffs().data(), x.t.data(), b.q.coeffs().data(), b.t.data(), no_correction.data(), &r);
      // The board's frame moved along its x: the points on its +x edge lie inside by the shift (its
      // corners stay on the outline's y edges), those on its -x edge outside by it.
      const bool on_x_edge = std::abs(std::abs(on_pattern.x()) - 0.5 * width) < 1e-12;
      const bool off = on_x_edge && (on_pattern.x() < 0.0 || std::abs(on_pattern.y()) < 1e-12);
      EXPECT_NEAR(std::abs(r), off ? shift / 0.005 : 0.0, 1e-9) << on_pattern.transpose();
    }
  }
  // Each edge's ends and middle (the corners twice), each on the outline.
  const std::vector<Eigen::Vector3d> outline = vocal::patternOutline(width, height);
  ASSERT_EQ(outline.size(), 12u);
  for (const Eigen::Vector3d& p : outline) EXPECT_NEAR(vocal::distanceToOutline(p.x(), p.y(), 0.5 * width, 0.5 * height), 0.0, 1e-12);
}

// A camera's whole PnP pose on the board: zero where the print's place puts the pattern where the view saw
// it; the print 5 mm / -3 mm off along the board's x / y and turned 10 mrad about its normal, read with the
// print at the centre, is 10 rotation sigmas of 1 mrad and sqrt(34) translation sigmas of 1 mm; its prior
// is its place in the prior's sigmas.
TEST(RigGraphResiduals, CameraPoseOnBoardIsTheViewAgainstThePrintOnTheBoard) {
  const Scene scene;
  const Eigen::Vector3d print(0.005, -0.003, 0.01);
  vocal::PlaneMeasurement view;
  view.sensor_from_pattern = scene.camera.inverse() * scene.board * Eigen::Translation3d(print.x(), print.y(), 0.0) *
                             Eigen::AngleAxisd(print.z(), Eigen::Vector3d::UnitZ());
  view.pose_covariance = 1e-6 * Eigen::Matrix<double, 6, 6>::Identity();
  const vocal::CameraPoseOnBoardResidual residual(view);
  const Blocks x(scene.camera), b(scene.board);
  Eigen::Matrix<double, 6, 1> r;
  ASSERT_TRUE(residual(x.q.coeffs().data(), x.t.data(), b.q.coeffs().data(), b.t.data(), print.data(), r.data()));
  EXPECT_LT(r.norm(), 1e-6);
  const Eigen::Vector3d centred = Eigen::Vector3d::Zero();
  ASSERT_TRUE(residual(x.q.coeffs().data(), x.t.data(), b.q.coeffs().data(), b.t.data(), centred.data(), r.data()));
  EXPECT_NEAR(r.head<3>().norm(), 10.0, 1e-3);
  EXPECT_NEAR(r.tail<3>().norm(), std::sqrt(34.0), 1e-3);
  // The turn is about the board's normal (the pattern's z: the rotation error is the pattern's own).
  EXPECT_NEAR(std::abs(r.head<3>().normalized().z()), 1.0, 1e-6);

  const vocal::PrintPlacePrior prior{0.01, 0.02};
  Eigen::Vector3d p;
  ASSERT_TRUE(prior(print.data(), p.data()));
  EXPECT_NEAR(p[0], 0.5, 1e-12);
  EXPECT_NEAR(p[1], -0.3, 1e-12);
  EXPECT_NEAR(p[2], 0.5, 1e-12);
}

// Cauchy's loss spread over a block: the square is c^2 log(1 + (r / c)^2) on either branch, the sign kept.
TEST(RigGraphResiduals, CauchyResidualSquaresToCauchysLoss) {
  for (const double c : {1.0, 3.0}) {
    for (const double r : {-7.0, -0.5, 1e-6, 2.0, 30.0}) {
      const double spread = vocal::cauchyResidual(r, c);
      EXPECT_NEAR(spread * spread, c * c * std::log1p(r * r / (c * c)), 1e-12 * (1.0 + r * r)) << r << " " << c;
      EXPECT_EQ(std::signbit(spread), std::signbit(r));
    }
  }
}

// A view's outline points in one block: each point's distance to the outline in the board's plane, in its
// sigmas, under Cauchy's loss, in order.
TEST(RigGraphResiduals, OutlinePointsAreEachPointsOutlineDistanceUnderCauchy) {
  const Scene scene;
  const double half_width = 0.3, half_height = 0.2, sigma = 0.01, loss = 3.0;
  const Eigen::Isometry3d camera_from_board = scene.camera.inverse() * scene.board;
  std::vector<Eigen::Vector3d> points;
  const std::vector<double> distances = {0.0, 0.02, 0.0, 0.3, -0.05};  // to the outline: on, 20 mm beyond, on, 300 mm beyond, inside
  for (const Eigen::Vector2d& on_board : {Eigen::Vector2d(0.3, 0.05), Eigen::Vector2d(0.32, -0.1), Eigen::Vector2d(-0.1, 0.2),
                                          Eigen::Vector2d(0.0, -0.5), Eigen::Vector2d(-0.25, 0.0)}) {
    points.push_back(camera_from_board * Eigen::Vector3d(on_board.x(), on_board.y(), 0.0));
  }
  const vocal::OutlinePointsResidual all{points, sigma, half_width, half_height, loss};
  const Blocks x(scene.camera), b(scene.board);
  std::vector<double> r(points.size());
  all(x.q.coeffs().data(), x.t.data(), b.q.coeffs().data(), b.t.data(), r.data());
  for (std::size_t i = 0; i < points.size(); ++i) EXPECT_NEAR(r[i], vocal::cauchyResidual(distances[i] / sigma, loss), 1e-9) << i;
  EXPECT_NEAR(r[3], loss * std::sqrt(std::log1p(100.0)), 1e-9);  // 30 sigmas out: 6.4 under Cauchy's loss, not 30
}

// The weak board prior: zero where the board started; its shift in metres and its turn in radians.
TEST(RigGraphResiduals, WeakBoardPriorIsTheShiftAndTurnFromTheStart) {
  const Scene scene;
  const vocal::WeakBoardPrior prior{Eigen::Quaterniond(scene.board.linear()), scene.board.translation()};
  const Eigen::Isometry3d moved = Eigen::Translation3d(0.1, -0.2, 0.05) * scene.board * pose(Eigen::Vector3d::Zero(), 0.02, {0, 0, 1});
  for (const bool same : {true, false}) {
    const Eigen::Isometry3d& at = same ? scene.board : moved;
    Blocks b(at);
    b.q.coeffs() = -b.q.coeffs();  // the same turn either sign
    Eigen::Matrix<double, 6, 1> r;
    prior(b.q.coeffs().data(), b.t.data(), r.data());
    EXPECT_NEAR((r.head<3>() - (at.translation() - scene.board.translation())).norm(), 0.0, 1e-12);
    EXPECT_NEAR(r.tail<3>().norm(), same ? 0.0 : 2.0 * std::sin(0.01), 1e-12);
    if (!same) EXPECT_NEAR(r[5], 2.0 * std::sin(0.01), 1e-12);  // the turn in the board's own frame: about its z
  }
}


// A sensor behind joints: its block at a still pose tied to its chain at the pose's readings (plus offsets
// and corrections) times its mount, the cost both graphs build (the arm's without a mount); a free origin's
// correction after the readings'. Zero where they agree; the tilt's reading 1 mrad off shows at 100 of the
// tie's 10 urad, a mount 1 mm off at 100 of its 10 um.
TEST(RigGraphResiduals, ASensorBehindJointsIsTiedToItsChainTimesItsMount) {
  std::vector<vocal::JointDescription> joints = vocal_test::panTiltJoints();
  joints[1].free_origin = true;
  const std::vector<int> chain = {0, 1};
  const std::vector<double> readings = {0.4, -0.3};
  const Eigen::Isometry3d mount = pose({0.03, 0.0, 0.05}, 0.2, {0, 1, 0});
  const Blocks placed(vocal::chainPose(joints, chain, {0.4 + 0.002 + 0.0005, -0.3 - 0.001}) * mount);
  std::unique_ptr<ceres::CostFunction> tie(vocal::linkFromJointsCost(&joints, chain, readings, true));
  ASSERT_EQ(tie->parameter_block_sizes(), (std::vector<int32_t>{4, 3, 4, 3, 1, 1, 1, 1, 6}));
  ASSERT_EQ(tie->num_residuals(), 6);
  const double offsets[] = {0.002, -0.001};
  const Eigen::Matrix<double, 6, 1> origin = Eigen::Matrix<double, 6, 1>::Zero();
  for (const double off : {0.0, 0.001}) {
    for (const double shift : {0.0, 0.001}) {
      const Blocks m(Eigen::Translation3d(shift, 0.0, 0.0) * mount);
      const double corrections[] = {0.0005, off};
      const double* blocks[] = {placed.q.coeffs().data(), placed.t.data(), m.q.coeffs().data(), m.t.data(), &offsets[0], &offsets[1],
                                &corrections[0], &corrections[1], origin.data()};
      Eigen::Matrix<double, 6, 1> r;
      ASSERT_TRUE(tie->Evaluate(blocks, r.data(), nullptr));
      EXPECT_NEAR(r.head<3>().norm(), off / 1e-5, 1e-3);
      if (off == 0.0) EXPECT_NEAR(r.tail<3>().norm(), shift / 1e-5, 1e-3);
    }
  }
  // Without a mount (the arm's links): the link's block against the chain alone.
  const Blocks link(vocal::chainPose(joints, chain, {0.4 + 0.002 + 0.0005, -0.3 - 0.001}));
  std::unique_ptr<ceres::CostFunction> link_tie(vocal::linkFromJointsCost(&joints, chain, readings));
  ASSERT_EQ(link_tie->parameter_block_sizes(), (std::vector<int32_t>{4, 3, 1, 1, 1, 1, 6}));
  const double corrections[] = {0.0005, 0.0};
  const double* blocks[] = {link.q.coeffs().data(), link.t.data(), &offsets[0], &offsets[1], &corrections[0], &corrections[1], origin.data()};
  Eigen::Matrix<double, 6, 1> r;
  ASSERT_TRUE(link_tie->Evaluate(blocks, r.data(), nullptr));
  EXPECT_LT(r.norm(), 1e-6);
}

// The views' scatter an arm's session measures (unmodelled_view_scatter.h): a camera on a reported tool
// over a board lying still, three views a still pose. Views that differ from the solution by their PnP
// noise alone: none. Views that share a 3 mm / 3 mrad error per axis within each still pose (a real arm's
// kinematics): that error per axis, within a third; and withViewScatter widens each view by it times its
// pose's view count.
TEST(RigGraphResiduals, TheViewsScatterIsWhatAStillPosesViewsShareBeyondTheirNoise) {
  std::mt19937 rng(5);
  std::normal_distribution<double> unit(0.0, 1.0);
  const Eigen::Isometry3d mount = Eigen::Translation3d(0.05, -0.03, -0.04) * Eigen::AngleAxisd(1.57, Eigen::Vector3d::UnitZ());
  const Eigen::Isometry3d board = Eigen::Translation3d(0.5, 0.0, 0.0) * Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitX());
  vocal::CalibrationResult solved;
  solved.sensors.resize(1);
  solved.sensors[0].reference_from_sensor = mount;
  solved.board_mount = board;
  solved.mounts.board_fixed = true;
  solved.mounts.on_reported_tool = {true};
  const std::vector<vocal::SensorSpec> sensors = {{"wrist_camera", vocal::SensorType::kCamera, "wrist"}};
  const double pnp_sigma = 1e-4;  // the views' PnP noise, per axis (rad, m)
  for (const double shared : {0.0, 0.003}) {
    SCOPED_TRACE("shared error " + std::to_string(shared));
    std::vector<vocal::TargetObservation> observations;
    for (int k = 0; k < 15; ++k) {
      const Eigen::Isometry3d tool = Eigen::Translation3d(0.4 + 0.02 * k, 0.1 * std::sin(k), 0.5) *
                                     Eigen::AngleAxisd(M_PI + 0.1 * std::cos(k), Eigen::Vector3d(0.2, 1.0, 0.1 * k).normalized());
      solved.mounts.tool_poses[k] = tool;
      const Eigen::Vector3d turn(shared * unit(rng), shared * unit(rng), shared * unit(rng));
      const Eigen::Vector3d shift(shared * unit(rng), shared * unit(rng), shared * unit(rng));
      vocal::TargetObservation o;
      o.sensor = 0, o.target_pose = k;
      for (int v = 0; v < 3; ++v) {
        vocal::PlaneMeasurement view;
        const Eigen::Vector3d w = turn + pnp_sigma * Eigen::Vector3d(unit(rng), unit(rng), unit(rng));
        const Eigen::Vector3d dt = shift + pnp_sigma * Eigen::Vector3d(unit(rng), unit(rng), unit(rng));
        const Eigen::Isometry3d truth = (tool * mount).inverse() * board;
        view.sensor_from_pattern.linear() = truth.linear() * Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix();
        view.sensor_from_pattern.translation() = truth.translation() + dt;
        view.pose_covariance = pnp_sigma * pnp_sigma * Eigen::Matrix<double, 6, 6>::Identity();
        o.plane_measurements.push_back(view);
      }
      observations.push_back(o);
    }
    const vocal::ViewScatter scatter = vocal::unmodelledViewScatter(sensors, observations, solved);
    if (shared == 0.0) {
      EXPECT_EQ(scatter.translation, 0.0);
      EXPECT_EQ(scatter.rotation, 0.0);
      continue;
    }
    EXPECT_NEAR(scatter.translation, shared, shared / 3);
    EXPECT_NEAR(scatter.rotation, shared, shared / 3);
    const std::vector<vocal::TargetObservation> widened = vocal::withViewScatter(observations, sensors, scatter);
    EXPECT_NEAR(widened[0].plane_measurements[0].pose_covariance(0, 0),
                pnp_sigma * pnp_sigma + 3 * scatter.rotation * scatter.rotation, 1e-12);
    EXPECT_NEAR(widened[0].plane_measurements[0].pose_covariance(5, 5),
                pnp_sigma * pnp_sigma + 3 * scatter.translation * scatter.translation, 1e-12);
  }
}
