#pragma once
// ---- MSG-Cal stage 1, extraction (calibration/extraction/): one sensor's message -> the target in it --
// In:  a camera image (pattern_observation.h: chessboard corners, PnP -> the board's plane with its
//      covariance and outline); a 3D lidar's or depth camera's cloud, or a 2D laser's scan (this file:
//      board-shaped candidates); over a session, which candidate is the board (static_background.h),
//      its edge points (board_outline.h), a spinning lidar's range offset per ring from the room's
//      planes (lidar_ring_offsets.h).
// Out: per message, the board's points and outline in the sensor's frame, or its plane measurement:
//      CalibrationSession turns them into TimedObservations for association/.
// ------------------------------------------------------------------------------------------------------
//
// Finding the target board in a range sensor's data: a 3D lidar's or depth sensor's cloud that also
// holds the floor, walls, furniture and the person holding the board, or a 2D laser's full scan.
// Geometry alone gives candidates (segments of the board's size and shape); which one is the board is
// for the caller to settle with what changes between poses (static_background.h).

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "vocal/calibration/extraction/surface_patch.h"

namespace vocal {

// An axis-aligned box in the sensor's frame: only points inside are searched (the rig YAML's
// per-sensor crop_box, for a room too cluttered to search whole).
struct CropBox {
  Eigen::Vector3d min = Eigen::Vector3d::Constant(-1e9), max = Eigen::Vector3d::Constant(1e9);
};

// How a sensor's returns are laid out: a spinning lidar's rings (constant elevation about its z axis,
// a 2D laser's one ring), a depth camera's pixel rows and columns (optical frame, z forward), or no scan
// lines at all (a solid-state lidar's non-repeating pattern, a cloud of unknown layout).
enum class ScanPattern { kSpinning, kPinhole, kScattered };

// Angles between neighbouring returns of a sensor, radians: within a lidar ring / image row
// (horizontal) and between rings / rows (vertical). Predicts how many points the board gives at a
// range and how far apart its neighbouring points may lie.
struct ScanSpacing {
  ScanSpacing(double horizontal_ = 0.0, double vertical_ = 0.0, ScanPattern pattern_ = ScanPattern::kSpinning)
      : horizontal(horizontal_), vertical(vertical_), pattern(pattern_) {}
  double horizontal = 0.0;
  double vertical = 0.0;
  ScanPattern pattern = ScanPattern::kSpinning;
  // A spinning lidar's ring elevations (radians, ascending; rings of 20 returns or more) when
  // estimateScanSpacing found its cloud to be one; empty otherwise.
  std::vector<double> rings;
  bool rings_from_driver = false;  // the cloud's ring field gave them (else: found by elevation)
  // Found on a scan cropped round the board without a ring field (estimateCroppedScanSpacing): `rings`
  // are the bands that scan showed, and each cloud's own bands (elevationBandsOf) stand in for them.
  bool rings_per_cloud = false;
};

struct TargetExtractionOptions {
  double plane_threshold = 0.04;    // metres from a board plane to count as its point (a VLP-16's noise is ~2 cm)
  double room_threshold = 0.06;     // ... from a room plane (floor, wall) removed before the search
  int max_room_planes = 8;          // room planes removed at most
  int max_planes_per_object = 6;    // planes tried in each cluster left over
  // RANSAC samples at most (fewer once a plane holds enough points to be sure): a room plane holds a
  // large share of the cloud, the board most of its object.
  int room_iterations = 150;
  int object_iterations = 300;
  double size_slack = 0.15;         // metres a segment's sides may exceed the board's by
  double min_area_fraction = 0.25;  // of the board's area: a partly seen board still counts
  double max_area_fraction = 1.35;
  // A segment up to this much of the board's area (and no longer than its diagonal + size_slack) may be
  // the board with the arms or chest that hold it in its plane: the board-sized rectangle holding the
  // most of its points is the board when it holds this share of them.
  double max_held_area_fraction = 2.0;
  double min_held_share = 0.7;
  // A board-sized segment over this much of the board's area and wider across than its shorter side
  // (+ half the slack) may be the board with the chest behind it: the board cut out of it as above is
  // taken when more board-like.
  double max_whole_area_fraction = 1.2;
  double min_density_fraction = 0.35;  // of the points the spacing predicts on the segment's own area
  double max_count_fraction = 2.5;     // of the points it predicts on the whole board
  // A spinning lidar's segment on fewer rings is no board: two rings leave the plane's tilt across them
  // to a few centimetres of height, one none (a small or far board; hold it nearer).
  int min_rings = 3;
  double edge_margin = 0.04;  // metres along the segment's outline left out of the points it gives (hands, mixed pixels)
  int min_points = 30;                 // 3D; a 2D segment needs 10 (RANSAC is PCL's, seeded with a constant)
  std::optional<CropBox> crop_box;
};

struct TargetCandidate {
  std::vector<Eigen::Vector3d> points;  // sensor frame, without the margin along its outline
  std::vector<Eigen::Vector3d> outline;  // sensor frame, on the board's edges (board_outline.h)
  double mismatch = 0.0;                // how unlike the board (log size and area ratios): 0 is the board seen whole
};

struct TargetSearch {
  std::vector<TargetCandidate> candidates;  // board-like segments, least mismatch first (then most points)
  std::string rejection;  // when there are none: why the most board-like segment was not taken
  std::string check;      // ... which check refused it: crop box, no segment, floor or wall, larger than the board,
                          // too few rings, smaller than the board, too few points, too many points
  // Planes larger than the board (floor, walls, large furniture; a 2D scan's long runs): most of the
  // time they cover what becomes a board-sized segment once someone stands in front of them.
  std::vector<SurfacePatch> surfaces;
  // A spinning lidar's room planes, each plane's returns (those of its pieces larger than the board):
  // what its ring offsets are estimated from (lidar_ring_offsets.h). Empty unless the spacing has rings.
  std::vector<std::vector<Eigen::Vector3d>> room_points;
};

// The board's candidates in a 3D cloud (lidar or depth, sensor frame): points outside the crop box
// dropped; room planes (planes with a connected piece larger than the board) removed by RANSAC;
// what is left split into objects by Euclidean clustering; in each, planes by RANSAC, their points
// clustered again; each cluster checked against the board's width, height (minimum-area rectangle),
// area (convex hull) and the point count `spacing` predicts. Throws InputError for spacing <= 0.
TargetSearch findTargetInCloud(const std::vector<Eigen::Vector3d>& cloud, double target_width, double target_height,
                               const ScanSpacing& spacing, const TargetExtractionOptions& options = {});

// The board's candidates in a 2D scan (points in the scan plane z = 0, in beam order, `beam_spacing`
// radians apart): RANSAC lines, each line's points split where neighbours are farther apart than the
// spacing allows; segments as long as the board's sides fit (at most its diagonal + slack).
TargetSearch findTargetInScan(const std::vector<Eigen::Vector3d>& scan, double target_width, double target_height,
                              double beam_spacing, const TargetExtractionOptions& options = {});

// A spinning lidar's ring and azimuth spacing from its cloud (elevations cluster into rings), with its
// rings; a dense cloud's (depth camera) from the angle to each point's nearest neighbour. Zero for < 10 points.
ScanSpacing estimateScanSpacing(const std::vector<Eigen::Vector3d>& cloud);

// The elevations (radians, ascending) of the bands a cloud's returns fall into, each of `least_returns`
// or more and much narrower than the gaps between them (a spinning lidar's rings, a scanning laser's
// sweeps); empty when its elevations do not fall into three such bands or more (a non-repeating pattern).
std::vector<double> elevationBandsOf(const std::vector<Eigen::Vector3d>& cloud, std::size_t least_returns = 5);

// The spacing of a scan cropped round the board and published without a ring field (too few returns for
// estimateScanSpacing's rings): its bands' gaps and the azimuth steps along its fullest band, and
// `rings_per_cloud` set; zero when its returns fall into no bands.
ScanSpacing estimateCroppedScanSpacing(const std::vector<Eigen::Vector3d>& cloud);

// The most board-like candidate's points (empty when none): for callers without a background model.
std::vector<Eigen::Vector3d> extractTargetPoints(const std::vector<Eigen::Vector3d>& cloud, double target_width,
                                                 double target_height, const TargetExtractionOptions& options = {});
std::vector<Eigen::Vector3d> extractTargetSegment(const std::vector<Eigen::Vector3d>& scan, double target_width,
                                                  double target_height, double beam_spacing,
                                                  const TargetExtractionOptions& options = {});

}  // namespace vocal
