#pragma once
// The fast CPU backend's preprocessed frame: per level, float planes (structure of arrays, for the
// streaming loops of preprocessing) and two per-pixel records that the tracking pass gathers from the
// reference frame at projected positions (one cache line per lookup instead of six planes).
// The math is frame_pyramid.cpp's, written to run over rows in parallel with vectorisable inner loops;
// buffers are reused frame after frame.

#include <vector>

#include "vocal/core/pinhole_camera.h"
#include "vocal/core/rgbd_frame.h"
#include "vocal/odometry/odometry_config.h"

namespace vocal {

class WorkerPool;

// Vertex and normal of one pixel in the camera frame; NaN where undefined.
struct SurfaceRecord {
  float vx, vy, vz, nx, ny, nz;
};

// What the photometric term reads at a (sub-)pixel: intensity, its gradients, the depth (0 = missing).
struct PhotometricRecord {
  float intensity, gradient_x, gradient_y, depth;
};

struct SoaPyramidLevel {
  PinholeCamera camera;
  int width = 0, height = 0;
  std::vector<float> depth;      // metres, 0 = missing
  std::vector<float> intensity;  // [0, 1]
  std::vector<float> gradient_x, gradient_y;  // Sobel / 8
  std::vector<SurfaceRecord> surface;
  std::vector<PhotometricRecord> photometric;
  // Level 0 only: the smoothed depth the normals come from, and its inverse-depth scratch (kept, so
  // that a frame allocates nothing).
  std::vector<float> smoothed_depth, inverse_depth;

  std::size_t memoryBytes() const;
};

using SoaFramePyramid = std::vector<SoaPyramidLevel>;

// Fills `pyramid` (resized and reused) with the same maps as buildFramePyramid, on `workers` (the same
// maps with any number of threads);
// `allow_avx2`: the AVX2 passes (depth smoothing, depth pyramid, vertex and normal records) where the
// CPU has AVX2, the same maps to the bit (false: the portable loops everywhere).
// `finest_level`: the levels finer than it keep only their depth and intensity (what the coarser ones are
// made from): no gradients, smoothed depth or records, for a frame that will not be tracked there.
void buildSoaFramePyramid(const RgbdFrame& frame, const PinholeCamera& camera, const OdometryConfig& config,
                          WorkerPool& workers, SoaFramePyramid* pyramid, bool allow_avx2 = true, int finest_level = 0);

}  // namespace vocal
