#pragma once
// One image row of the fast CPU backend's tracking pass: the current frame's pixels warped into the
// reference, the ICP and photometric rows they give (the tests and Jacobians of CpuOdometryBackend),
// added to packed normal-equation sums (NormalEquations::fromPacked's layout). Two implementations:
// a portable one (any CPU; the compiler vectorises its reduction) and an 8-pixel AVX2 + FMA one with
// hardware gathers, picked at run time where the CPU has it.

#include <Eigen/Geometry>

#include "vocal/core/pinhole_camera.h"
#include "vocal/odometry/depth_noise_model.h"
#include "vocal/odometry/fast_cpu_backend.h"
#include "vocal/odometry/soa_frame_pyramid.h"

namespace vocal {

// The current-to-reference transform, the reference level's intrinsics and the current intensity as
// the reference sees it (gain * I + bias), in float.
struct TrackingWarp {
  TrackingWarp(const Eigen::Isometry3d& reference_from_current, const PinholeCamera& camera,
               const BrightnessTransfer& brightness);
  float r[9], t[3];
  float fx, fy, cx, cy;
  float gain, bias;
};

struct TrackingThresholds {
  float max_distance_squared, min_cos, max_depth, max_depth_difference, min_gradient_squared, huber;
  DepthNoiseModel depth_noise;  // weights the ICP pairs
};

// TrackRowFunction (fast_cpu_backend.h): adds row y's rows to icp_sums / rgb_sums (29 values each;
// nullptr = that term is off): within the row in float, onto the sums in double.
void trackRowPortable(const SoaPyramidLevel& cur, const SoaPyramidLevel& ref, const TrackingWarp& warp,
                      const TrackingThresholds& thresholds, int y, double* icp_sums, double* rgb_sums);

// The AVX2 + FMA row, or nullptr where this build or this CPU has no AVX2.
TrackRowFunction avx2TrackRow();

}  // namespace vocal
