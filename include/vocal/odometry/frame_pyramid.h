#pragma once
// CPU reference preprocessing of one RGB-D frame into the per-level maps the odometry uses. The OpenCL
// kernels in cl_kernels/ compute the same maps.

#include <vector>

#include <Eigen/Core>

#include "vocal/core/image.h"
#include "vocal/core/pinhole_camera.h"
#include "vocal/core/rgbd_frame.h"
#include "vocal/odometry/odometry_config.h"

namespace vocal {

struct PyramidLevel {
  PinholeCamera camera;
  DepthImage depth;            // metres, 0 = missing
  Image<float> intensity;      // [0, 1]
  Image<float> gradient_x;     // Sobel / 8: intensity per pixel
  Image<float> gradient_y;
  Image<Eigen::Vector3f> vertices;  // camera frame; NaN where depth is missing
  Image<Eigen::Vector3f> normals;   // unit, facing the camera; NaN where undefined
};

using FramePyramid = std::vector<PyramidLevel>;

FramePyramid buildFramePyramid(const RgbdFrame& frame, const PinholeCamera& camera, const OdometryConfig& config);

// The individual steps, exposed for tests.
Image<float> intensityFromColor(const ColorImage& color);
DepthImage sanitizeDepth(const DepthImage& depth, double min_depth, double max_depth);
DepthImage smoothDepth(const DepthImage& depth, int radius, float factor);
DepthImage downsampleDepth(const DepthImage& depth, double sigma);
Image<float> downsampleIntensity(const Image<float>& intensity);

}  // namespace vocal
