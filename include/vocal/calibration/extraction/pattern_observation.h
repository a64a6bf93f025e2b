#pragma once
// A camera's view of the target: the pattern's pose from its detected corners (PnP), turned into the
// corners' 3D positions in the camera frame (for initialisation and residuals) and a plane measurement
// with its covariance (for the graph).

#include <vector>

#include <Eigen/Core>

#include "vocal/calibration/calibration_types.h"
#include "vocal/core/image.h"
#include "vocal/core/lens_distortion.h"
#include "vocal/core/pinhole_camera.h"

namespace vocal {

struct TargetPattern {
  int rows = 6;               // inner corners
  int cols = 8;
  double square_size = 0.06;  // metres

  // Corner positions in the target frame (z = 0), centred on the target, row by row.
  std::vector<Eigen::Vector3d> corners() const;
};

constexpr double kMisdetectedCornerPixels = 1.0;
constexpr double kMisdetectedCornerMedians = 6.0;

struct PatternObservation {
  std::vector<Eigen::Vector3d> points;  // the corners in the camera frame
  double reprojection_rms_px = 0.0;  // of the corners used
  // Corners (indices into TargetPattern::corners()) left out of the pose as misdetected: each over
  // kMisdetectedCornerPixels and kMisdetectedCornerMedians times the median corner's error, at most a tenth.
  std::vector<int> corners_left_out;
  // The pattern's pose and its plane's covariance from the PnP covariance (reprojection Jacobian,
  // pixel noise taken from the reprojection error, at least 0.05 px).
  PlaneMeasurement plane;
};

// The pattern's inner corners in an image, sub-pixel refined, in the order of TargetPattern::corners()
// up to the board's 180-degree symmetry (which leaves the plane unchanged). Throws InputError naming
// `what` when the board is not found.
std::vector<Eigen::Vector2d> detectPattern(const ColorImage& image, const TargetPattern& pattern, const char* what);

// `image_corners` are pixels of the image as taken, through the lens's `distortion` (camera_info's D):
// the pose is fitted to the undistorted corners, the reprojection error and the covariance are those
// of the distorted pixels; a corner far off the pose the others give is left out (corners_left_out).
// Throws InputError naming `what` when the corner count does not match the pattern or the pose cannot
// be estimated.
PatternObservation observePattern(const std::vector<Eigen::Vector2d>& image_corners, const TargetPattern& pattern,
                                  const PinholeCamera& camera, const char* what, const LensDistortion& distortion = {});

}  // namespace vocal
