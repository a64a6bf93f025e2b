#include "vocal/odometry/cpu_backend.h"

#include <cmath>

#include "vocal/odometry/depth_noise_model.h"

namespace vocal {

namespace {
// The motion and the reference camera in float, as the kernels see them.
struct FloatWarp {
  FloatWarp(const Eigen::Isometry3d& reference_from_current, const PinholeCamera& camera)
      : R(reference_from_current.linear().cast<float>()),
        t(reference_from_current.translation().cast<float>()),
        fx(static_cast<float>(camera.fx)),
        fy(static_cast<float>(camera.fy)),
        cx(static_cast<float>(camera.cx)),
        cy(static_cast<float>(camera.cy)) {}
  Eigen::Matrix3f R;
  Eigen::Vector3f t;
  float fx, fy, cx, cy;
};

float bilinear(const Image<float>& image, float u, float v) {
  const int x = static_cast<int>(u), y = static_cast<int>(v);
  const float a = u - x, b = v - y;
  return (1 - b) * ((1 - a) * image(x, y) + a * image(x + 1, y)) + b * ((1 - a) * image(x, y + 1) + a * image(x + 1, y + 1));
}
}  // namespace

CpuOdometryBackend::CpuOdometryBackend(const PinholeCamera& camera, const OdometryConfig& config)
    : camera_(camera), config_(config) {}

void CpuOdometryBackend::pushFrame(const RgbdFrame& frame, ReferenceUpdate update) {
  if (update == ReferenceUpdate::kPreviousFrame) reference_ = std::move(current_);
  current_ = buildFramePyramid(frame, camera_, config_);
}

NormalEquations CpuOdometryBackend::icpSystem(int level, const Eigen::Isometry3d& reference_from_current) {
  const PyramidLevel& cur = current_.at(level);
  const PyramidLevel& ref = reference_.at(level);
  const FloatWarp warp(reference_from_current, ref.camera);
  const float max_distance = static_cast<float>(config_.icp_max_distance);
  const float min_cos = static_cast<float>(std::cos(config_.icp_max_angle_deg * M_PI / 180.0));
  const DepthNoiseModel depth_noise(config_.depth_noise_floor, config_.depth_noise_quadratic);
  NormalEquations system;
  const int step = rowStep(level);
  for (int y = 0; y < cur.vertices.height(); y += step) {
    for (int x = 0; x < cur.vertices.width(); ++x) {
      const Eigen::Vector3f& vc = cur.vertices(x, y);
      const Eigen::Vector3f& nc = cur.normals(x, y);
      if (std::isnan(vc.z()) || std::isnan(nc.z())) continue;
      const Eigen::Vector3f p = warp.R * vc + warp.t;
      if (!(p.z() > 0.0f)) continue;
      // Projective data association: the reference pixel the point falls into.
      const int u = static_cast<int>(std::floor(warp.fx * p.x() / p.z() + warp.cx + 0.5f));
      const int v = static_cast<int>(std::floor(warp.fy * p.y() / p.z() + warp.cy + 0.5f));
      if (u < 0 || v < 0 || u >= ref.vertices.width() || v >= ref.vertices.height()) continue;
      const Eigen::Vector3f& vr = ref.vertices(u, v);
      const Eigen::Vector3f& nr = ref.normals(u, v);
      if (std::isnan(vr.z()) || std::isnan(nr.z())) continue;
      if ((p - vr).norm() > max_distance || (warp.R * nc).dot(nr) < min_cos) continue;
      const float r = nr.dot(p - vr);
      Vector6d J;
      J.head<3>() = nr.cast<double>();
      J.tail<3>() = p.cross(nr).cast<double>();
      system.addRow(J, r, depth_noise.icpWeight(p.z(), vr.z()), true);
    }
  }
  system *= step;
  return system;
}

NormalEquations CpuOdometryBackend::rgbSystem(int level, const Eigen::Isometry3d& reference_from_current,
                                              double huber_threshold, const BrightnessTransfer& brightness) {
  const PyramidLevel& cur = current_.at(level);
  const PyramidLevel& ref = reference_.at(level);
  const FloatWarp warp(reference_from_current, ref.camera);
  const float max_depth = static_cast<float>(config_.rgb_max_depth);
  const float max_depth_difference = static_cast<float>(config_.rgb_max_depth_difference);
  const float min_gradient = static_cast<float>(config_.rgb_min_gradient.at(level));
  const float huber = static_cast<float>(huber_threshold);
  const int w = ref.depth.width(), h = ref.depth.height();
  NormalEquations system;
  const int step = rowStep(level);
  for (int y = 0; y < cur.depth.height(); y += step) {
    for (int x = 0; x < cur.depth.width(); ++x) {
      const Eigen::Vector3f& vc = cur.vertices(x, y);
      if (std::isnan(vc.z()) || vc.z() > max_depth) continue;
      // Warp the current pixel with its depth into the reference image.
      const Eigen::Vector3f p = warp.R * vc + warp.t;
      if (!(p.z() > 0.0f)) continue;
      const float qu = warp.fx * p.x() / p.z() + warp.cx, qv = warp.fy * p.y() / p.z() + warp.cy;
      if (!(qu >= 0.0f && qv >= 0.0f && qu < w - 1 && qv < h - 1)) continue;
      const float zr = ref.depth(static_cast<int>(qu + 0.5f), static_cast<int>(qv + 0.5f));
      if (!(zr > 0.0f) || zr > max_depth || std::fabs(zr - p.z()) > max_depth_difference) continue;
      const float gx = bilinear(ref.gradient_x, qu, qv), gy = bilinear(ref.gradient_y, qu, qv);
      if (gx * gx + gy * gy < min_gradient * min_gradient) continue;
      const float r = bilinear(ref.intensity, qu, qv) - (brightness.gain * cur.intensity(x, y) + brightness.bias);
      // d r / d p of the projection, then d p / d twist = [I, -[p]x].
      const float z_inv = 1.0f / p.z();
      const Eigen::Vector3f a(gx * warp.fx * z_inv, gy * warp.fy * z_inv,
                            -(gx * warp.fx * p.x() + gy * warp.fy * p.y()) * z_inv * z_inv);
      Vector6d J;
      J.head<3>() = a.cast<double>();
      J.tail<3>() = p.cross(a).cast<double>();
      const float abs_r = std::fabs(r);
      const double weight = abs_r <= huber ? 1.0 : huber / abs_r;
      system.addRow(J, r, weight);
    }
  }
  system *= step;
  return system;
}

std::size_t CpuOdometryBackend::memoryBytes() const {
  std::size_t bytes = 0;
  for (const FramePyramid* pyramid : {&reference_, &current_}) {
    for (const PyramidLevel& l : *pyramid) {
      bytes += l.depth.size() * sizeof(float) * 4 + l.vertices.size() * sizeof(Eigen::Vector3f) * 2;
    }
  }
  return bytes;
}

}  // namespace vocal
