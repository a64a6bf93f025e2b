#pragma once
// Coloured 3D points of an RGB-D frame, for clouds shown in rviz.

#include <vector>

#include <Eigen/Core>

#include "vocal/core/image.h"
#include "vocal/core/pinhole_camera.h"
#include "vocal/core/rgbd_frame.h"

namespace vocal {

struct ColoredPoint {
  Eigen::Vector3f position;
  Rgb8 color;
};

// The frame's pixels with valid depth, every `stride`-th in x and y, in the camera frame.
std::vector<ColoredPoint> backProjectFrame(const RgbdFrame& frame, const PinholeCamera& camera, int stride);

}  // namespace vocal
