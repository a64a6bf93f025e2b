#pragma once
// What the estimator needs from a compute backend: keep a reference and a current frame preprocessed
// into pyramids, and build the ICP and DVO normal equations of one pyramid level for a given motion.
// The CPU reference and the OpenCL backend implement the same math (parity-tested).

#include <algorithm>
#include <memory>
#include <string>

#include <Eigen/Geometry>

#include "vocal/core/pinhole_camera.h"
#include "vocal/core/rgbd_frame.h"
#include "vocal/odometry/brightness_transfer.h"
#include "vocal/odometry/normal_equations.h"
#include "vocal/odometry/odometry_config.h"

namespace vocal {

// What pushing a frame does to the reference: the previous frame becomes it (frame-to-frame tracking,
// or a new keyframe), or it stays (tracking against a keyframe; the previous current frame is dropped).
enum class ReferenceUpdate { kPreviousFrame, kKeep };

class WorkerPool;

class OdometryBackend {
 public:
  virtual ~OdometryBackend() = default;

  // Human-readable backend and device, e.g. "opencl: NVIDIA H100 (NVIDIA CUDA)".
  virtual std::string name() const = 0;

  // Preprocesses `frame` (intensity, depth pyramid, vertex and normal maps, gradients) as the new
  // current frame; `update` says whether the previous current frame becomes the reference. The frame
  // must match the camera the backend was made for (the estimator checks).
  virtual void pushFrame(const RgbdFrame& frame, ReferenceUpdate update) = 0;
  // The finest level the frames pushed from now on will be tracked at: a backend may leave the finer
  // levels' maps and gradients out (building only what the coarser levels are made from). The caller
  // pushes a frame again before tracking it at a finer level. Ignored by default (every level built).
  virtual void setFinestLevel(int /*level*/) {}
  // The systems of `level` from one row in `step` (the others at every row), each sum times `step` so
  // that they stand for the whole image: a CPU's finest level at a fraction of its cost, nearly all of
  // its precision (the coarser level has a quarter of the pixels and of the detail). Returns whether the
  // backend does so (samplesRows); one that does not (a GPU's: no time to save) builds every row. Step
  // 1: every row.
  bool setSampledRows(int level, int step) {
    if (step > 1 && !samplesRows()) return false;
    sampled_level_ = level;
    sampled_row_step_ = std::max(1, step);
    return true;
  }
  // Whether the backend builds a level's systems from sampled rows (setSampledRows).
  virtual bool samplesRows() const { return false; }

  // Systems in the twist of a left update of reference_from_current (x = [v; w], T <- exp(x) T). The
  // photometric residual compares the reference's intensity with the current one mapped by
  // `brightness` (gain * I + bias).
  virtual NormalEquations icpSystem(int level, const Eigen::Isometry3d& reference_from_current) = 0;
  virtual NormalEquations rgbSystem(int level, const Eigen::Isometry3d& reference_from_current,
                                    double huber_threshold, const BrightnessTransfer& brightness) = 0;
  // Both systems of one level for one motion (either pointer may be null: that term is not built).
  // This calls icpSystem and rgbSystem; a backend that builds both in one pass over the pixels
  // overrides it.
  virtual void trackingSystems(int level, const Eigen::Isometry3d& reference_from_current, double huber_threshold,
                               const BrightnessTransfer& brightness, NormalEquations* icp, NormalEquations* rgb);

  // Bytes of frame buffers the backend holds (both frames, all levels).
  virtual std::size_t memoryBytes() const = 0;

  // The threads the backend runs its loops on, for the estimator's own (rectification, brightness
  // transfer) to share; null where the backend has none (its work runs elsewhere, e.g. on a GPU).
  virtual WorkerPool* workers() { return nullptr; }

 protected:
  // The step between the rows `level`'s systems are built from (setSampledRows; 1: every row).
  int rowStep(int level) const { return level == sampled_level_ ? sampled_row_step_ : 1; }

 private:
  int sampled_level_ = 0, sampled_row_step_ = 1;
};

// Camera of pyramid level `level`: samples sit at (2^level x, 2^level y) of the input, so the
// intrinsics simply scale by 2^-level.
PinholeCamera pyramidLevelCamera(const PinholeCamera& camera, int level);

// Makes the backend the config asks for. kAuto: OpenCL on a GPU when one is there, else the fast CPU
// backend (`notice` says which and why). kOpenCl throws InputError naming what was found when no
// device is usable (a CPU device such as PoCL's counts).
std::unique_ptr<OdometryBackend> makeOdometryBackend(const PinholeCamera& camera, const OdometryConfig& config,
                                                     std::string* notice = nullptr);

}  // namespace vocal
