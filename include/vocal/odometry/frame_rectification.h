#pragma once
// What a real RGB-D camera's frame departs from the pinhole, global-shutter model the odometry's
// terms assume, undone before tracking:
//  - lens distortion (camera_info's D: TUM freiburg1's k1 = 0.26 moves corner pixels by ten);
//  - a rolling shutter: rows are read one after another over `readout` seconds (a Kinect's colour
//    sensor, and its depth registered to it), so a moving camera sees each row from another pose; on
//    TUM freiburg1 this leaked 20-30 mm/s of rotation into translation;
//  - depth taken at another instant than the colour (`depth_time_offset`): its own lookups, from that
//    instant (TUM freiburg1's Kinect: about 5 ms before; its stamps do not say so).
// Each output pixel is looked up where a global-shutter pinhole camera at the middle row's instant
// would find it in the input: turned by the camera's rotation over the time between its row and the
// middle one, shifted by its translation over that time at the depth found there (constant velocity,
// the last measured), then distorted. Colour is interpolated bilinearly, depth taken from the nearest
// pixel (interpolating across an edge would invent surfaces). A lookup outside the input gives no depth
// and the nearest border pixel's colour: black there was an edge moving with the estimated motion,
// which the photometric term tracked. Depth values are kept as measured:
// moving them to the middle instant too (first order in the motion) made freiburg1_xyz 12 % worse in
// RPE, although a rendered rolling-shutter depth sensor would want it. The rotation's lookup is exact
// on a grid of nodes every kGridStep pixels and interpolated between them (the map is smooth).

#include <vector>

#include <Eigen/Core>

#include "vocal/core/lens_distortion.h"
#include "vocal/core/pinhole_camera.h"
#include "vocal/core/rgbd_frame.h"

namespace vocal {

class WorkerPool;

class FrameRectification {
 public:
  static constexpr int kGridStep = 8;

  FrameRectification() = default;  // nothing to undo
  // `readout_seconds`: from the first row's exposure to the last's (0: global shutter).
  // `depth_time_offset`: seconds the depth is taken after the colour; it is turned to the colour's instant.
  // `allow_avx2`: 8 pixels at a time where the CPU has AVX2 (the same output as the portable loop,
  // to the bit; false: the portable loop everywhere).
  FrameRectification(const PinholeCamera& camera, const LensDistortion& lens, double readout_seconds,
                     double depth_time_offset = 0.0, bool allow_avx2 = true);

  // Whether frames need rectifying at all (a lens to undistort or a rolling shutter).
  bool active() const { return !lens_.isNone() || readout_ > 0.0 || depth_time_offset_ != 0.0; }
  // Whether the result depends on the camera's motion (a rolling shutter, or depth taken at another
  // instant); the lens alone does not, so a frame rectified at rest need not be rectified again.
  bool dependsOnMotion() const { return readout_ > 0.0 || depth_time_offset_ != 0.0; }
  // The frame as the ideal camera would have seen it; `angular_velocity` (rad/s, in the camera frame,
  // as the twist of odometry <- camera(t)) turns the rows of a rolling shutter. The frame must have
  // the camera's size. On `workers` where given (the same output with any number of threads).
  RgbdFrame rectify(const RgbdFrame& frame, const Eigen::Vector3d& angular_velocity,
                    const Eigen::Vector3d& linear_velocity = Eigen::Vector3d::Zero(), WorkerPool* workers = nullptr) const;
  // Where the ideal camera's pixel (u, v) is found in the input image (exact; `rectify` interpolates
  // this between grid nodes). NaN when the lens model does not reach it.
  // `time_offset`: seconds added to every row's instant (the depth's capture after the colour's).
  Eigen::Vector2d sourcePixel(double u, double v, const Eigen::Vector3d& angular_velocity, double time_offset = 0.0) const;

 private:
  PinholeCamera camera_;
  LensDistortion lens_;
  double readout_ = 0.0;
  double depth_time_offset_ = 0.0;
  bool avx2_ = false;
};

}  // namespace vocal
