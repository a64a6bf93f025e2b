#pragma once
// What a user checks a calibration by, per still pose and camera: the range sensors' board points carried
// into the camera by the calibrated extrinsics, drawn over its image through its lens beside the board
// the camera itself saw (its detected corners, the board's outline from PnP), and counted: how many land
// on that board and how far off its plane they lie. The camera's PnP is independent of the range
// sensors, so a wrong extrinsic shows as points beside or off the board.

#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "vocal/core/image.h"
#include "vocal/core/lens_distortion.h"
#include "vocal/core/pinhole_camera.h"

namespace vocal {

// One range sensor's board points in the camera frame, as the calibration puts them.
struct OverlayLayer {
  std::string label;  // the sensor's name
  Rgb8 colour;
  std::vector<Eigen::Vector3d> points;
};

struct OverlayAgreement {
  int points = 0;
  double on_board = 0.0;   // fraction within the board's outline (plus `margin`), measured in its plane
  double plane_rms = 0.0;  // metres, the points' distance to the board's plane
};

// `camera_from_board`: the board's pose as the camera saw it (centred, x along its width, z its normal).
OverlayAgreement overlayAgreement(const std::vector<Eigen::Vector3d>& points, const Eigen::Isometry3d& camera_from_board,
                                  double width, double height, double margin = 0.02);

struct OverlayBoard {
  std::vector<Eigen::Vector2d> corners;  // the pattern's detected corners, pixels
  Eigen::Isometry3d camera_from_board = Eigen::Isometry3d::Identity();
  double width = 0.0, height = 0.0;  // 0: no board drawn (the camera did not find it)
};

// A colour copy of `image` with the board (its outline green, corners as small crosses) and each layer's
// points as dots of its colour, a legend in the top-left corner. Points behind the camera or outside
// the image are left out.
ColorImage drawCalibrationOverlay(const ColorImage& image, const PinholeCamera& camera, const LensDistortion& lens,
                                  const OverlayBoard& board, const std::vector<OverlayLayer>& layers,
                                  const std::string& title);

// An overlay scaled down to `width` pixels across (its aspect kept) over a strip holding `label` - what
// is still readable at that size.
ColorImage labelledThumbnail(const ColorImage& image, int width, const std::string& label);

// The thumbnails in rows of `columns`, left to right, each in a cell as large as the largest, on dark
// grey (an empty image leaves its cell empty): every pose and camera in one image.
ColorImage contactSheet(const std::vector<ColorImage>& thumbnails, int columns);

}  // namespace vocal
