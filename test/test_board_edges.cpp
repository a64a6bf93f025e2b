// The board's outline in MSG-Cal: where range sensors see its edges, and the graph that holds them,
// against simulated rigs whose target is tilted only up and down (normals of little spread).

#include <gtest/gtest.h>

#include "test_support.h"

#include <cmath>
#include <iostream>
#include <random>
#include <set>

#include "vocal/calibration/extraction/board_outline.h"
#include "vocal/calibration/solver/scan_ends.h"
#include "vocal/calibration/solver/graph_calibration.h"
#include "vocal/core/se3.h"
#include "vocal/simulation/rig_simulator.h"
#include "vocal/simulation/simulated_sensor_data.h"

namespace {
std::vector<vocal::SensorSpec> specs(const vocal::SimulatedRig& rig) {
  std::vector<vocal::SensorSpec> out;
  for (const auto& s : rig.sensors) out.push_back(s.spec);
  return out;
}

// RGB-D reference, a second RGB-D, a lidar, a 2D laser and a camera; 20 poses tilted up to 0.6 rad up
// and down but turned at most 0.03 rad left or right; a VLP-16's 2 cm range noise on every range sensor.
vocal::SimulatedRig weakSpreadRig(std::uint32_t seed) {
  vocal::RigSimulationOptions options;
  options.target_poses = 20;
  options.turn_range = 0.03;
  options.range_noise = 0.02;
  options.pixel_noise = 0.5;
  options.seed = seed;
  return vocal::simulateRig(vocal::exampleRig(2, 1, 1, 1), options);
}

vocal::CalibrationOptions edgeOptions(const vocal::SimulatedRig& rig, const vocal::RigSimulationOptions& simulated = {}) {
  vocal::CalibrationOptions options;
  options.reference_pose = rig.sensors[0].reference_from_sensor;
  options.board_edges.enabled = true;
  options.board_edges.width = simulated.target_width;
  options.board_edges.height = simulated.target_height;
  return options;
}
}  // namespace

TEST(BoardOutline, DistanceToTheOutlineIsSignedAndZeroOnTheEdges) {
  EXPECT_DOUBLE_EQ(vocal::distanceToOutline(0.45, 0.1, 0.45, 0.35), 0.0);   // on the right edge
  EXPECT_DOUBLE_EQ(vocal::distanceToOutline(-0.2, -0.35, 0.45, 0.35), 0.0); // on the bottom edge
  EXPECT_DOUBLE_EQ(vocal::distanceToOutline(0.0, 0.0, 0.45, 0.35), -0.35);  // the centre: nearest are top and bottom
  EXPECT_DOUBLE_EQ(vocal::distanceToOutline(0.5, 0.0, 0.45, 0.35), 0.05);   // beside the right edge
  EXPECT_NEAR(vocal::distanceToOutline(0.48, -0.39, 0.45, 0.35), 0.05, 1e-12);  // beyond a corner
}

// A lidar without rings (a Livox's non-repeating pattern: returns scattered over the board, no scan
// lines): rows and columns of its directions stand in for lines, and their ends lie on the board's
// edges, all round, to within about the mean spacing. (Taken as lines split at gaps in elevation, the
// scattered returns made one "line" whose two ends were corners: a Livox session's lidar 39 mm off.)
TEST(BoardOutline, AScatteredPatternEndsOnTheBoardsEdgesAllRound) {
  const double half_width = 0.45, half_height = 0.35, range = 2.0, spacing = 0.01;  // radians between returns, on average
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> across(-1.0, 1.0);
  // The board 2 m ahead along x, facing the lidar, turned 0.3 rad about its vertical.
  Eigen::Isometry3d sensor_from_board = Eigen::Isometry3d::Identity();
  sensor_from_board.linear() = Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()).toRotationMatrix() * vocal::targetFacingRig();
  sensor_from_board.translation() = Eigen::Vector3d(range, 0.0, 0.0);
  std::vector<Eigen::Vector3d> points;
  const int count = static_cast<int>(4 * half_width * half_height / std::pow(range * spacing, 2));
  for (int i = 0; i < count; ++i) points.push_back(sensor_from_board * Eigen::Vector3d(half_width * across(rng), half_height * across(rng), 0.0));
  const Eigen::Vector3d normal = sensor_from_board.linear().col(2);
  const std::vector<Eigen::Vector3d> outline = vocal::boardOutlinePoints(
      points, vocal::Plane{normal, -normal.dot(sensor_from_board.translation())}, vocal::ScanSpacing(spacing, spacing, vocal::ScanPattern::kScattered));
  ASSERT_GT(outline.size(), 40u);
  int left = 0, right = 0, top = 0, bottom = 0;
  for (const Eigen::Vector3d& p : outline) {
    const Eigen::Vector3d on_board = sensor_from_board.inverse() * p;
    EXPECT_LT(std::abs(vocal::distanceToOutline(on_board.x(), on_board.y(), half_width, half_height)), 2.0 * range * spacing)
        << on_board.transpose();
    left += on_board.x() < -0.8 * half_width, right += on_board.x() > 0.8 * half_width;
    bottom += on_board.y() < -0.8 * half_height, top += on_board.y() > 0.8 * half_height;
  }
  EXPECT_GT(std::min({left, right, top, bottom}), 5) << left << " " << right << " " << top << " " << bottom;
}

TEST(BoardOutline, EachLidarRingEndsOnTheBoardsEdges) {
  const vocal::SimulatedSensor lidar = vocal::exampleRig(0, 1)[0];
  vocal::RigSimulationOptions options;  // noise-free: the ends are off the edges by the azimuth step only
  const double half_width = 0.45, half_height = 0.35;
  std::mt19937 rng(3);
  for (double tilt : {0.0, 0.4, -0.5}) {
    Eigen::Isometry3d reference_from_target = Eigen::Isometry3d::Identity();
    reference_from_target.linear() = vocal::rotationFromRollPitchYaw(0.3, tilt, 0.2) * vocal::targetFacingRig();
    reference_from_target.translation() = lidar.reference_from_sensor.translation() + Eigen::Vector3d(2.0, 0.1, 0.05);
    const vocal::TargetObservation seen = vocal::observeTarget(lidar, reference_from_target, half_width, half_height, options, &rng);
    ASSERT_FALSE(seen.points.empty());
    // Rings on the board: the distinct elevations among its points.
    std::set<long> rings;
    for (const Eigen::Vector3d& p : seen.points) rings.insert(std::lround(std::atan2(p.z(), p.head<2>().norm()) * 180.0 / M_PI));
    EXPECT_EQ(seen.outline.size(), 2 * rings.size()) << "tilt " << tilt;
    const Eigen::Isometry3d target_from_sensor = reference_from_target.inverse() * lidar.reference_from_sensor;
    const double step = 2.0 * 0.2 * M_PI / 180.0 * 2.5;  // metres: an azimuth step at 2.5 m, with room for the slant
    for (const Eigen::Vector3d& p : seen.outline) {
      const Eigen::Vector3d on_board = target_from_sensor * p;
      EXPECT_NEAR(on_board.z(), 0.0, 1e-9);  // in the board's plane
      EXPECT_LT(std::abs(vocal::distanceToOutline(on_board.x(), on_board.y(), half_width, half_height)), step)
          << "tilt " << tilt << " at " << on_board.transpose();
    }
  }
}

// A 2D laser's beam as wide as a SICK LMS1xx's (8 mm + 15 mrad x range across, by its manual) before a
// board 1 m away facing it: the returns run on past each side by the beam's radius there (4 + 7.5 = 11.5
// mm, less up to a step between beams, 4.4 mm), each at about the board's range; a ray's stop within a
// step inside the sides.
TEST(BoardOutline, AWideBeamSeesTheBoardPastItsEdgesByItsRadius) {
  vocal::TargetDescription target;
  target.width = 0.4;
  target.height = 0.3;
  const vocal::SimulatedSensor laser{{"laser", vocal::SensorType::kLaser2d, "laser"}, Eigen::Isometry3d::Identity()};
  vocal::SimulatedRoomView view;
  view.sensor = &laser;
  view.target = &target;
  view.reference_from_target.translation() = Eigen::Vector3d(1.0, 0.05, 0.02);
  view.reference_from_target.linear() = vocal::targetFacingRig();
  for (const bool wide : {false, true}) {
    view.beam_aperture = wide ? 0.008 : 0.0;
    view.beam_divergence = wide ? 0.015 : 0.0;
    std::mt19937 rng(1);
    const std::vector<float> ranges = vocal::simulateLaserRanges(view, &rng);
    double left = 1.0, right = -1.0;  // the board's returns' extent across (laser y)
    for (std::size_t i = 0; i < ranges.size(); ++i) {
      if (!(ranges[i] < 1.1)) continue;
      const double azimuth = (-135.0 + 0.25 * i) * M_PI / 180.0;
      // On the board's plane (a wide beam's edge returns: the range of the part of the board nearest its centre).
      EXPECT_NEAR(ranges[i] * std::cos(azimuth), 1.0, wide ? 3e-3 : 1e-6) << i;
      left = std::min(left, ranges[i] * std::sin(azimuth)), right = std::max(right, ranges[i] * std::sin(azimuth));
    }
    const double past = wide ? 0.004 + 0.0075 * 1.0 : 0.0, step = 0.25 * M_PI / 180.0;
    EXPECT_NEAR(right - 0.05, 0.2 + past - 0.5 * step, 0.5 * step + 2e-3) << wide;
    EXPECT_NEAR(0.05 - left, 0.2 + past - 0.5 * step, 0.5 * step + 2e-3) << wide;
  }
}

// A scan end's sigma: where its edge lies within the beams' step at its range (uniform: step / sqrt(12)),
// stretched along a board turned away, with the floor (kLeastScanEndSigma), and shared by the scans of one still station;
// and where a noisy scan's line fit puts it.
TEST(BoardOutline, AScanEndsSigmaIsItsStepAtItsRangeSharedByTheStationsScans) {
  const double step = 0.25 * M_PI / 180.0;
  // A line 1 m ahead facing the laser, and the same turned 60 degrees (its points' range grows along it).
  for (const double turned : {0.0, M_PI / 3}) {
    std::vector<Eigen::Vector3d> points;
    for (int i = -20; i <= 20; ++i) {
      const double bearing = i * step, range = 1.0 / (std::cos(bearing) - std::tan(turned) * std::sin(bearing));
      points.push_back(range * Eigen::Vector3d(std::cos(bearing), std::sin(bearing), 0.0));
    }
    EXPECT_NEAR(vocal::beamStep(points), step, 1e-9);
    const std::vector<Eigen::Vector3d> ends = {points.front(), points.back()};
    for (const int scans : {1, 4}) {
      const vocal::LaserScanEnds one = vocal::scanEndsOf(ends, points, 1, scans);
      ASSERT_EQ(one.sigmas.size(), 2u);
      for (int e = 0; e < 2; ++e) {
        const Eigen::Vector3d& end = ends[e];
        const Eigen::Vector3d along = (ends[1] - ends[0]).normalized();
        const double stretch = 1.0 / std::abs(Eigen::Vector3d(-along.y(), along.x(), 0.0).dot(end.normalized()));
        EXPECT_NEAR(one.sigmas[e], std::sqrt(scans) * std::hypot(step * end.norm() * stretch / std::sqrt(12.0), vocal::kLeastScanEndSigma), 1e-9)
            << turned << " " << e;
      }
    }
    // With 1 cm of range noise, one scan's line fit moves an end along the line too, as far as its beam
    // slants to the line's normal: more for the turned board, each scan's own (not times sqrt(scans)).
    std::mt19937 rng(3);
    std::normal_distribution<double> noise(0.0, 0.01);
    std::vector<Eigen::Vector3d> noisy;
    for (const Eigen::Vector3d& p : points) noisy.push_back((p.norm() + noise(rng)) * p.normalized());
    const double exact = vocal::scanEndsOf(ends, points, 1, 1).sigmas[1], fitted = vocal::scanEndsOf(ends, noisy, 1, 1).sigmas[1];
    if (turned == 0.0) {
      EXPECT_NEAR(fitted, exact, 0.1 * exact);
    } else {
      EXPECT_GT(fitted, 1.2 * exact);
    }
  }
}

TEST(BoardEdges, PlaneOnlyRefusesATargetTiltedOnlyUpAndDown) {
  const vocal::SimulatedRig rig = weakSpreadRig(5);
  vocal::CalibrationOptions options = edgeOptions(rig);
  options.board_edges.enabled = false;
  const std::string error = vocal_test::inputErrorOf([&] { vocal::calibrateRig(specs(rig), rig.observations, options); });
  EXPECT_NE(error.find("the target planes are too close to parallel"), std::string::npos) << error;
}

TEST(BoardEdges, EdgesFixEverySensorOfATargetTiltedOnlyUpAndDown) {
  for (std::uint32_t seed : {5u, 6u}) {
    const vocal::SimulatedRig rig = weakSpreadRig(seed);
    const vocal::CalibrationResult result = vocal::calibrateRig(specs(rig), rig.observations, edgeOptions(rig));
    EXPECT_TRUE(result.trusted) << result.failure;
    // The weak direction is still reported before solving.
    EXPECT_FALSE(result.warnings.empty());
    for (std::size_t s = 1; s < rig.sensors.size(); ++s) {
      const Eigen::Isometry3d difference = rig.sensors[s].reference_from_sensor.inverse() * result.sensors[s].reference_from_sensor;
      std::cout << rig.sensors[s].spec.name << " seed " << seed << ": " << difference.translation().norm() * 1000 << " mm, "
                << vocal::rotationAngle(difference) << " rad, reported sigma " << result.sensors[s].standard_deviation.head<3>().norm() * 1000
                << " mm\n";
      EXPECT_LT(difference.translation().norm(), 0.01) << rig.sensors[s].spec.name << " seed " << seed;
      EXPECT_LT(vocal::rotationAngle(difference), 0.01) << rig.sensors[s].spec.name << " seed " << seed;
      EXPECT_GT(result.sensors[s].standard_deviation.head<3>().norm(), 0.0) << rig.sensors[s].spec.name;
    }
  }
}

TEST(BoardEdges, WithoutTheBoardsSizeEdgesAreRefused) {
  const vocal::SimulatedRig rig = weakSpreadRig(5);
  vocal::CalibrationOptions options = edgeOptions(rig);
  options.board_edges.height = 0.0;
  EXPECT_EQ(vocal_test::inputErrorOf([&] { vocal::calibrateRig(specs(rig), rig.observations, options); }),
            "calibration: board edges need the board's width and height (got 0.900000 x 0.000000 m)");
}
