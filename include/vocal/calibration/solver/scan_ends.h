#pragma once
// A 2D laser's scan ends as both graphs hold them on the board's outline (outline_points_residual.h): where
// each end lies and how well the beams' step places it.
// Eigen only.

#include <vector>

#include <Eigen/Core>

#include "vocal/calibration/solver/outline_points_residual.h"

namespace vocal {

// A scan end's sigma is at least this (metres): the board's plate cut and measured to a millimetre.
constexpr double kLeastScanEndSigma = 0.001;

struct LaserScanEnds {
  std::vector<Eigen::Vector3d> points;  // sensor frame, on the scan's line (boardOutlinePoints)
  std::vector<double> sigmas;           // per end, metres across the board's edge
};

// The angle between a 2D laser's neighbouring beams (radians): the median step between the bearings of a
// view's points (one scan's or several of the same beams); 0 for fewer than two bearings.
double beamStep(const std::vector<Eigen::Vector3d>& points);

// How many scans `ends` (several scans' ends pooled, as a still pose's observation pools them) come from:
// their count over the number of distinct bearings among them (a still board's scans end on the same
// beams); at least 1.
int scansOfPooledEnds(const std::vector<Eigen::Vector3d>& ends);

// `ends` of a scan whose board points are `line_points` (sensor frame, the scan in its x-y plane; with
// `pooled` scans of a still board pooled, all of theirs), each end one of `scans` scans' of the same still
// board. Each end's sigma along the board's edge normal, at most its move along the line: where the
// edge lies within the beams' step at its range (boardOutlinePoints puts it half a step out: a uniform
// spread of step / sqrt(12), stretched along the line), at least kLeastScanEndSigma, the same for every
// scan of a still board and so counted once over them (times sqrt(scans)); and where one scan's own line
// fit puts the end (its points' scatter across the line, moved along it by the beam's slant).
LaserScanEnds scanEndsOf(const std::vector<Eigen::Vector3d>& ends, const std::vector<Eigen::Vector3d>& line_points, int pooled, int scans);

// The ends on a `width` x `height` plate's outline, each in its own sigma, under a Cauchy loss of
// `loss_sigmas` (a finger over the edge ends a line early): the residual both graphs hold them by (with the
// laser's beam: OutlinePointsResidual::withBeam).
OutlinePointsResidual scanEndsOnOutline(const LaserScanEnds& ends, double width, double height, double loss_sigmas);

}  // namespace vocal
