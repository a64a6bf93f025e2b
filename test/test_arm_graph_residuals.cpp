// The arm graph's residual kinds (calibration/solver/*_residual.h), each on its own: zero where the
// unknowns agree with the observation, and the observation's error in its standard deviations where they
// are off by a known amount.
#include <gtest/gtest.h>

#include "graph_residual_support.h"

#include <cmath>
#include <vector>

#include <Eigen/Geometry>

#include "vocal/calibration/solver/beam_range_view_residual.h"
#include "vocal/calibration/solver/camera_view_residual.h"
#include "vocal/calibration/solver/frame_mounting.h"
#include "vocal/calibration/solver/joint_origin_prior.h"
#include "vocal/calibration/solver/link_from_joints_residual.h"
#include "vocal/calibration/solver/outline_view_residual.h"
#include "vocal/calibration/solver/range_view_residual.h"
#include "vocal/calibration/solver/reading_corrections_residual.h"
#include "vocal/calibration/solver/tool_pose_residual.h"
#include "vocal/core/se3.h"

namespace {
using vocal_test::Blocks;
using vocal_test::pose;

// A sensor on the tool over a fixed board, or fixed before a board on the tool: the frames of one still pose.
struct Scene {
  Eigen::Isometry3d sensor = pose({0.05, -0.02, 0.1}, 0.3, {1, 2, 3});    // in its parent
  Eigen::Isometry3d board = pose({0.6, 0.1, -0.2}, 2.5, {0.2, 1, 0.1});   // in its parent
  Eigen::Isometry3d sensor_frame = pose({0.3, 0.4, 0.5}, 0.7, {0, 0, 1});
  Eigen::Isometry3d board_frame = pose({-0.1, 0.2, 0.3}, 0.4, {1, 0, 1});
};
}  // namespace

// The templated mounting (the residuals') and the plain one (the start-up's) put the board alike, for a
// sensor and a board each fixed or moving.
TEST(ArmGraphResiduals, FrameMountingTemplatedAndPlainAgree) {
  const Scene scene;
  for (const bool sensor_moves : {false, true}) {
    for (const bool board_moves : {false, true}) {
      const vocal::FrameMounting mounting{sensor_moves, board_moves};
      const Blocks board(scene.board), sensor_frame(scene.sensor_frame), board_frame(scene.board_frame);
      const double* blocks[] = {board.q.coeffs().data(), board.t.data(), sensor_frame.q.coeffs().data(), sensor_frame.t.data(),
                                board_frame.q.coeffs().data(), board_frame.t.data()};
      const auto [q, t] = mounting.boardInSensorParent(blocks);
      const Eigen::Isometry3d plain = mounting.boardInSensorParent(scene.board, scene.sensor_frame, scene.board_frame);
      Eigen::Isometry3d expected = scene.board;
      if (board_moves) expected = scene.board_frame * expected;
      if (sensor_moves) expected = scene.sensor_frame.inverse() * expected;
      EXPECT_LT((plain.matrix() - expected.matrix()).norm(), 1e-12);
      EXPECT_LT((t - expected.translation()).norm(), 1e-12);
      EXPECT_LT(vocal::rotationAngle(Eigen::Isometry3d(q.toRotationMatrix()).inverse() * Eigen::Isometry3d(expected.linear())), 1e-9);
    }
  }
}

// A camera's view: zero at the pose the unknowns predict; a camera 2 mm off along its x, with a 1 mm
// standard deviation there, is 2 standard deviations off along x alone.
TEST(ArmGraphResiduals, CameraViewIsThePnpPoseErrorInItsSigmas) {
  const Scene scene;
  const vocal::FrameMounting mounting{true, false};
  vocal::PlaneMeasurement view;
  view.sensor_from_pattern = scene.sensor.inverse() * mounting.boardInSensorParent(scene.board, scene.sensor_frame, scene.board_frame);
  view.pose_covariance = Eigen::Matrix<double, 6, 6>::Identity() * 1e-6;  // 1 mrad, 1 mm
  const vocal::CameraViewResidual residual(view, mounting);
  const Blocks board(scene.board), sensor_frame(scene.sensor_frame), board_frame(scene.board_frame);
  const auto evaluate = [&](const Eigen::Isometry3d& camera) {
    const Blocks x(camera);
    Eigen::Matrix<double, 6, 1> r;
    residual(x.q.coeffs().data(), x.t.data(), board.q.coeffs().data(), board.t.data(), sensor_frame.q.coeffs().data(), sensor_frame.t.data(),
             board_frame.q.coeffs().data(), board_frame.t.data(), r.data());
    return r;
  };
  EXPECT_LT(evaluate(scene.sensor).norm(), 1e-6);
  // The camera 2 mm along its own x: the board seen 2 mm along -x.
  const Eigen::Matrix<double, 6, 1> off = evaluate(scene.sensor * Eigen::Translation3d(0.002, 0.0, 0.0));
  EXPECT_NEAR(off[3], -2.0, 1e-6);
  EXPECT_LT(off.head<3>().norm() + std::abs(off[4]) + std::abs(off[5]), 1e-6);
}

// A range sensor's board points: zero on the board's plane; moved 10 mm off it with 5 mm of noise, the
// squared residual is the points' count times 4.
TEST(ArmGraphResiduals, RangeViewIsThePointsDistanceToTheBoardsPlane) {
  const Scene scene;
  const vocal::FrameMounting mounting{false, true};
  const Eigen::Isometry3d sensor_from_board = scene.sensor.inverse() * mounting.boardInSensorParent(scene.board, scene.sensor_frame, scene.board_frame);
  std::vector<Eigen::Vector3d> on, off;
  for (double x = -0.15; x <= 0.15; x += 0.05) {
    for (double y = -0.1; y <= 0.1; y += 0.05) {
      on.push_back(sensor_from_board * Eigen::Vector3d(x, y, 0.0));
      off.push_back(sensor_from_board * Eigen::Vector3d(x, y, 0.01));
    }
  }
  const Blocks x(scene.sensor), board(scene.board), sensor_frame(scene.sensor_frame), board_frame(scene.board_frame);
  for (const bool shifted : {false, true}) {
    const vocal::RangeViewResidual residual(shifted ? off : on, 0.005, mounting);
    Eigen::Vector4d r;
    residual(x.q.coeffs().data(), x.t.data(), board.q.coeffs().data(), board.t.data(), sensor_frame.q.coeffs().data(), sensor_frame.t.data(),
             board_frame.q.coeffs().data(), board_frame.t.data(), r.data());
    EXPECT_NEAR(r.squaredNorm(), shifted ? 4.0 * static_cast<double>(on.size()) : 0.0, 1e-6);
  }
}

// A 2D laser's points as range errors along its beams: a board 1 m ahead facing the laser, moved 20 mm
// further, leaves each beam 20 mm short, 2 standard deviations of 10 mm, over the cosine of its incidence.
TEST(ArmGraphResiduals, BeamRangeViewIsTheRangeErrorAlongEachBeam) {
  const vocal::FrameMounting mounting{false, false};
  const Eigen::Isometry3d board = pose({1.0, 0.0, 0.0}, -M_PI / 2, {0, 1, 0});  // its z towards the laser
  std::vector<Eigen::Vector3d> points;
  for (const double y : {-0.1, 0.0, 0.1}) points.push_back({1.0, y, 0.0});
  const vocal::BeamRangeViewResidual residual{points, 0.01, mounting};
  const Blocks laser(Eigen::Isometry3d::Identity()), identity(Eigen::Isometry3d::Identity());
  for (const double shift : {0.0, 0.02}) {
    const Blocks at(Eigen::Translation3d(shift, 0.0, 0.0) * board);
    const double* blocks[] = {laser.q.coeffs().data(), laser.t.data(), at.q.coeffs().data(), at.t.data(), identity.q.coeffs().data(),
                              identity.t.data(), identity.q.coeffs().data(), identity.t.data()};
    double r[3];
    residual(blocks, r);
    for (std::size_t i = 0; i < points.size(); ++i) EXPECT_NEAR(std::abs(r[i]), 2.0 * shift / 0.02 * points[i].norm(), 1e-9) << i;
  }
}

// A scan's ends on the board's outline: zero on its edge, 1 standard deviation (10 mm) 10 mm beyond it,
// under Cauchy's loss of 3 sigmas.
TEST(ArmGraphResiduals, OutlineViewIsTheEndsDistanceToTheBoardsEdge) {
  const Scene scene;
  const vocal::FrameMounting mounting{true, true};
  const Eigen::Isometry3d sensor_from_board = scene.sensor.inverse() * mounting.boardInSensorParent(scene.board, scene.sensor_frame, scene.board_frame);
  const Blocks x(scene.sensor), board(scene.board), sensor_frame(scene.sensor_frame), board_frame(scene.board_frame);
  for (const double beyond : {0.0, 0.01}) {
    const std::vector<Eigen::Vector3d> ends = {sensor_from_board * Eigen::Vector3d(0.18 + beyond, 0.05, 0.0),
                                               sensor_from_board * Eigen::Vector3d(-0.18, -0.02, 0.0)};
    const vocal::OutlineViewResidual residual{{ends, 0.01, 0.18, 0.135, 3.0}, mounting};
    double r[2];
    const double none[] = {0.0, 0.0};
    residual(x.q.coeffs().data(), x.t.data(), board.q.coeffs().data(), board.t.data(), sensor_frame.q.coeffs().data(), sensor_frame.t.data(),
             board_frame.q.coeffs().data(), board_frame.t.data(), none, r);
    EXPECT_NEAR(r[0], vocal::cauchyResidual(beyond / 0.01, 3.0), 1e-9);
    EXPECT_NEAR(r[1], 0.0, 1e-9);
  }
}

// A wide beam's scan ends reach past the board's edge by its footprint there: a beam of radius 5 mm + 5 mrad
// x range is 10 mm in radius at 1 m. An end 1 m along the laser's x: facing the board it lies 10 mm past
// a side; with the board turned 0.6 rad about its y axis, 10 / cos(0.6) mm past the edges across that
// turn (the footprint stretched) and still 10 mm past those along it. Each is zero there, 1 sigma a
// millimetre further; with a beam of radius zero (a ray) it is the distance to the edge.
TEST(ArmGraphResiduals, OutlineViewEndsReachPastTheEdgeByTheBeamsFootprint) {
  const vocal::FrameMounting mounting{false, false};
  const Blocks laser(Eigen::Isometry3d::Identity()), identity(Eigen::Isometry3d::Identity());
  const double beam[] = {0.005, 0.005}, ray[] = {0.0, 0.0};
  const Eigen::Vector3d end(1.0, 0.0, 0.0);
  for (const double turned : {0.0, 0.6}) {
    // The board's z back towards the laser, turned about its own y; its x edges across the turn.
    const Eigen::Matrix3d turn = (Eigen::AngleAxisd(M_PI / 2, -Eigen::Vector3d::UnitY()) * Eigen::AngleAxisd(turned, Eigen::Vector3d::UnitY())).toRotationMatrix();
    for (const bool across_turn : {true, false}) {
      const double past = across_turn ? 0.010 / std::cos(turned) : 0.010;
      for (const double beyond : {0.0, 0.001}) {
        // The board placed so that the end lies `past + beyond` outside its edge.
        const Eigen::Vector3d on_board = across_turn ? Eigen::Vector3d(0.18 + past + beyond, 0.02, 0.0) : Eigen::Vector3d(0.03, 0.135 + past + beyond, 0.0);
        Eigen::Isometry3d board = Eigen::Isometry3d::Identity();
        board.linear() = turn;
        board.translation() = end - turn * on_board;
        const Blocks at(board);
        const vocal::OutlineViewResidual residual{{{end}, 0.01, 0.18, 0.135, 30.0, {0.001}}, mounting};
        double r = 0.0;
        residual(laser.q.coeffs().data(), laser.t.data(), at.q.coeffs().data(), at.t.data(), identity.q.coeffs().data(), identity.t.data(),
                 identity.q.coeffs().data(), identity.t.data(), beam, &r);
        EXPECT_NEAR(r, vocal::cauchyResidual(beyond / 0.001, 30.0), 1e-6) << turned << " " << across_turn;
        residual(laser.q.coeffs().data(), laser.t.data(), at.q.coeffs().data(), at.t.data(), identity.q.coeffs().data(), identity.t.data(),
                 identity.q.coeffs().data(), identity.t.data(), ray, &r);
        EXPECT_NEAR(r, vocal::cauchyResidual((past + beyond) / 0.001, 30.0), 1e-6);
      }
    }
  }
}

// The arm's reported tool: zero at the report, 3 sigmas for 0.3 mm off with a 0.1 mm repeatability.
TEST(ArmGraphResiduals, ToolPoseIsTheDepartureFromTheReportInTheArmsRepeatability) {
  const Eigen::Isometry3d reported = pose({0.4, 0.1, 0.3}, 1.0, {1, 1, 0});
  const vocal::ToolPoseResidual residual(reported, 1e-4, 1e-4);
  for (const double shift : {0.0, 3e-4}) {
    const Blocks tool(Eigen::Translation3d(0.0, shift, 0.0) * reported);
    Eigen::Matrix<double, 6, 1> r;
    residual(tool.q.coeffs().data(), tool.t.data(), r.data());
    EXPECT_NEAR(r.norm(), shift / 1e-4, 1e-6);
    EXPECT_NEAR(r[4], shift / 1e-4, 1e-6);
  }
}

// A frame from its joints: zero where the chain puts it; a first joint's offset 1 mrad off turns the
// chain's end by 1 mrad about that joint's axis, 100 of the tie's 10 urad.
TEST(ArmGraphResiduals, LinkFromJointsTiesTheFrameToItsChain) {
  const std::vector<vocal::JointDescription> joints = vocal_test::panTiltJoints();
  const std::vector<int> chain = {0, 1};
  const std::vector<double> readings = {0.4, -0.3};
  const vocal::LinkFromJointsResidual residual{&joints, chain, readings};
  const Blocks frame(vocal::chainPose(joints, chain, readings, {0.0, 0.0}));
  for (const double offset : {0.0, 1e-3}) {
    const double offsets[] = {offset, 0.0}, corrections[] = {0.0, 0.0};
    const double* blocks[] = {frame.q.coeffs().data(), frame.t.data(), &offsets[0], &offsets[1], &corrections[0], &corrections[1]};
    Eigen::Matrix<double, 6, 1> r;
    residual(blocks, r.data());
    EXPECT_NEAR(r.head<3>().norm(), offset / 1e-5, 1e-3);
    if (offset > 0.0) {
      EXPECT_GT(std::abs(r.head<3>().normalized().dot(frame.q.conjugate() * Eigen::Vector3d::UnitZ())), 0.999);
    }
  }
}

// A free origin in the tie (JointDescription::free_origin): zero where the chain with the corrected origin
// puts the frame; the origin's correction block follows the reading corrections; a turn about the joint's
// own axis is its offset's and moves nothing; the prior counts each part in its sigma.
TEST(ArmGraphResiduals, AFreeOriginMovesTheChainItIsOn) {
  std::vector<vocal::JointDescription> joints(2);
  joints[0].name = "shoulder", joints[0].parent = "base", joints[0].child = "upper_arm", joints[0].axis = Eigen::Vector3d::UnitY();
  joints[0].origin.translation() = Eigen::Vector3d(0.0, 0.0, 0.2);
  joints[1].name = "elbow", joints[1].parent = "upper_arm", joints[1].child = "forearm", joints[1].axis = Eigen::Vector3d::UnitY();
  joints[1].origin.translation() = Eigen::Vector3d(0.0, -0.05, 0.5);
  joints[1].free_origin = true;
  const std::vector<int> chain = {0, 1};
  const std::vector<double> readings = {0.4, -0.7};
  Eigen::Matrix<double, 6, 1> correction;
  correction << 0.002, 0.0, -0.001, 0.0, 0.001, 0.01;  // turns about x, z and the upper arm 1 cm longer
  std::vector<vocal::JointDescription> corrected = joints;
  corrected[1].origin = vocal::jointOriginCorrected(joints[1], correction);
  EXPECT_NEAR(corrected[1].origin.translation().z(), 0.51, 1e-12);
  const vocal::LinkFromJointsResidual residual{&joints, chain, readings};
  const Blocks frame(vocal::chainPose(corrected, chain, readings, {0.0, 0.0}));
  const double offsets[] = {0.0, 0.0}, corrections[] = {0.0, 0.0};
  const double* blocks[] = {frame.q.coeffs().data(), frame.t.data(), &offsets[0], &offsets[1], &corrections[0], &corrections[1], correction.data()};
  Eigen::Matrix<double, 6, 1> r;
  residual(blocks, r.data());
  EXPECT_LT(r.norm(), 1e-6);
  // The same frame against the model's origin: the 1 cm shows, at 1000 of the tie's 10 um.
  const Eigen::Matrix<double, 6, 1> none = Eigen::Matrix<double, 6, 1>::Zero();
  const double* model[] = {frame.q.coeffs().data(), frame.t.data(), &offsets[0], &offsets[1], &corrections[0], &corrections[1], none.data()};
  residual(model, r.data());
  EXPECT_GT(r.tail<3>().norm(), 900.0);
  // A turn about the elbow's own axis (y) is the elbow's offset: the origin drops it.
  Eigen::Matrix<double, 6, 1> about_axis = Eigen::Matrix<double, 6, 1>::Zero();
  about_axis[1] = 0.05;
  EXPECT_TRUE(vocal::jointOriginCorrected(joints[1], about_axis).isApprox(joints[1].origin, 1e-15));

  const vocal::JointOriginPrior prior{0.01, 0.005};
  double p[6];
  prior(correction.data(), p);
  EXPECT_DOUBLE_EQ(p[0], 0.2);
  EXPECT_DOUBLE_EQ(p[5], 2.0);
}

// A still pose's reading corrections, each in its joint's sigma.
TEST(ArmGraphResiduals, ReadingCorrectionsAreInTheirSigmas) {
  const vocal::ReadingCorrectionsResidual residual{{0.001, 0.0005}};
  const double a = 0.002, b = -0.0005;
  const double* blocks[] = {&a, &b};
  double r[2];
  residual(blocks, r);
  EXPECT_DOUBLE_EQ(r[0], 2.0);
  EXPECT_DOUBLE_EQ(r[1], -1.0);
}
