#include "vocal/odometry/frame_rectification.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Geometry>

namespace vocal {

FrameRectification::FrameRectification(const PinholeCamera& camera, const LensDistortion& lens, double readout_seconds,
                                       double depth_time_offset)
    : camera_(camera), lens_(lens), readout_(readout_seconds), depth_time_offset_(depth_time_offset) {}

Eigen::Vector2d FrameRectification::sourcePixel(double u, double v, const Eigen::Vector3d& angular_velocity,
                                                double time_offset) const {
  const Eigen::Vector3d ideal((u - camera_.cx) / camera_.fx, (v - camera_.cy) / camera_.fy, 1.0);
  const double rate = angular_velocity.norm();
  const Eigen::Vector3d axis = rate > 0.0 ? Eigen::Vector3d(angular_velocity / rate) : Eigen::Vector3d::UnitZ();
  // The row is the source's; start from the output's and correct once (rows move by a pixel or two).
  double row = v;
  Eigen::Vector2d pixel(u, v);
  for (int step = 0; step < 2; ++step) {
    const double seconds_after_middle = time_offset + readout_ * (row / camera_.height - 0.5);
    // The camera at the row's instant is the middle one turned by rate * seconds about the axis; a
    // direction it sees is turned back.
    const Eigen::Vector3d seen = Eigen::AngleAxisd(-rate * seconds_after_middle, axis) * ideal;
    if (!(seen.z() > 0.0)) return Eigen::Vector2d::Constant(std::numeric_limits<double>::quiet_NaN());
    const Eigen::Vector2d distorted = lens_.distort(seen.head<2>() / seen.z());
    pixel = {camera_.fx * distorted.x() + camera_.cx, camera_.fy * distorted.y() + camera_.cy};
    if (readout_ == 0.0 || rate == 0.0) break;
    row = pixel.y();
  }
  return pixel;
}

RgbdFrame FrameRectification::rectify(const RgbdFrame& frame, const Eigen::Vector3d& angular_velocity,
                                      const Eigen::Vector3d& linear_velocity) const {
  const int w = camera_.width, h = camera_.height;
  // The lookup at grid nodes every kGridStep pixels (one node past the last row and column).
  const int nodes_x = (w - 1) / kGridStep + 2, nodes_y = (h - 1) / kGridStep + 2;
  auto lookupGrid = [&](double time_offset) {
    std::vector<Eigen::Vector2f> grid(static_cast<std::size_t>(nodes_x) * nodes_y);
#pragma omp parallel for schedule(static)
    for (int j = 0; j < nodes_y; ++j)
      for (int i = 0; i < nodes_x; ++i)
        grid[static_cast<std::size_t>(j) * nodes_x + i] =
            sourcePixel(i * kGridStep, j * kGridStep, angular_velocity, time_offset).cast<float>();
    return grid;
  };
  const std::vector<Eigen::Vector2f> nodes = lookupGrid(0.0);
  // Depth taken at another instant than the colour gets its own lookups, turned from that instant.
  const bool depth_apart =
      depth_time_offset_ != 0.0 && (angular_velocity.squaredNorm() > 0.0 || linear_velocity.squaredNorm() > 0.0);
  const std::vector<Eigen::Vector2f> depth_nodes = depth_apart ? lookupGrid(depth_time_offset_) : std::vector<Eigen::Vector2f>();

  RgbdFrame out;
  out.stamp = frame.stamp;
  out.color = ColorImage(w, h);
  out.depth = DepthImage(w, h, 0.0f);
  // The camera's own move over a row's offset from the middle one shifts near points more than far
  // ones: (fx (t_x - x t_z), fy (t_y - y t_z)) / z pixels for t = velocity * seconds, x, y the ideal
  // normalised coordinates, z the depth found (the lens's stretch of that shift is left out).
  const Eigen::Vector3f moving = (linear_velocity * readout_).cast<float>();
  const Eigen::Vector3f velocity = linear_velocity.cast<float>();
  const float depth_offset = static_cast<float>(depth_time_offset_), readout = static_cast<float>(readout_);
  const bool colour_translating = moving.squaredNorm() > 0.0f, translating = linear_velocity.squaredNorm() > 0.0;
  const float fx = static_cast<float>(camera_.fx), fy = static_cast<float>(camera_.fy);
  const float cx = static_cast<float>(camera_.cx), cy = static_cast<float>(camera_.cy);
  const Rgb8* colour_in = frame.color.data();
  const float* depth_in = frame.depth.data();
  const float max_x = w - 1.0f, max_y = h - 1.0f;
#pragma omp parallel for schedule(static)
  for (int v = 0; v < h; ++v) {
    // The row's lookups at the grid's columns (between its node rows), then linear along the row.
    const int j = v / kGridStep;
    const float b = static_cast<float>(v - j * kGridStep) / kGridStep;
    const Eigen::Vector2f* top = &nodes[static_cast<std::size_t>(j) * nodes_x];
    const Eigen::Vector2f* bottom = top + nodes_x;
    const Eigen::Vector2f* depth_top = depth_apart ? &depth_nodes[static_cast<std::size_t>(j) * nodes_x] : nullptr;
    Rgb8* colour_out = &out.color(0, v);
    float* depth_out = &out.depth(0, v);
    const float y_ideal = (v - cy) / fy;
    for (int i = 0; i + 1 < nodes_x && i * kGridStep < w; ++i) {
      const Eigen::Vector2f left = top[i] + b * (bottom[i] - top[i]);
      const Eigen::Vector2f step = (top[i + 1] + b * (bottom[i + 1] - top[i + 1]) - left) / static_cast<float>(kGridStep);
      Eigen::Vector2f depth_left = Eigen::Vector2f::Zero(), depth_step = Eigen::Vector2f::Zero();
      if (depth_apart) {
        const Eigen::Vector2f* depth_bottom = depth_top + nodes_x;
        depth_left = depth_top[i] + b * (depth_bottom[i] - depth_top[i]);
        depth_step = (depth_top[i + 1] + b * (depth_bottom[i + 1] - depth_top[i + 1]) - depth_left) / static_cast<float>(kGridStep);
      }
      const int u_end = std::min(w, (i + 1) * kGridStep);
      for (int u = i * kGridStep; u < u_end; ++u) {
        float sx = left.x() + (u - i * kGridStep) * step.x(), sy = left.y() + (u - i * kGridStep) * step.y();
        // NaN (no lookup) fails these tests too.
        bool seen = sx >= 0.0f && sy >= 0.0f && sx <= max_x && sy <= max_y;
        if (seen && colour_translating) {
          const float z = depth_in[static_cast<std::size_t>(sy + 0.5f) * w + static_cast<std::size_t>(sx + 0.5f)];
          if (isValidDepth(z)) {
            const float share = sy / h - 0.5f;  // of the readout, after the middle row
            const float x_ideal = (u - cx) / fx;
            sx -= fx * share * (moving.x() - x_ideal * moving.z()) / z;
            sy -= fy * share * (moving.y() - y_ideal * moving.z()) / z;
            seen = sx >= 0.0f && sy >= 0.0f && sx <= max_x && sy <= max_y;
          }
        }
        if (!seen) {
          // Outside the input: no depth, and the colour of the nearest border pixel. Black there made an
          // edge that moves with the estimated motion, not with the scene, and the photometric term
          // tracked it (in an untextured room it outweighed the scene's creases: DVO then turned
          // against the true rotation).
          sx = std::clamp(std::isnan(sx) ? static_cast<float>(u) : sx, 0.0f, max_x);
          sy = std::clamp(std::isnan(sy) ? static_cast<float>(v) : sy, 0.0f, max_y);
        }
        const int x = std::min(static_cast<int>(sx), w - 2), y = std::min(static_cast<int>(sy), h - 2);
        const float fa = sx - x, fb = sy - y;
        // Bilinear in 8-bit fixed point: weights summing to 65536.
        const int wa = static_cast<int>(fa * 256.0f + 0.5f), wb = static_cast<int>(fb * 256.0f + 0.5f);
        const int w00 = (256 - wa) * (256 - wb), w10 = wa * (256 - wb), w01 = (256 - wa) * wb, w11 = wa * wb;
        const Rgb8* p = colour_in + static_cast<std::size_t>(y) * w + x;
        const Rgb8 &p00 = p[0], &p10 = p[1], &p01 = p[w], &p11 = p[w + 1];
        colour_out[u] = {static_cast<std::uint8_t>((w00 * p00.r + w10 * p10.r + w01 * p01.r + w11 * p11.r + 32768) >> 16),
                         static_cast<std::uint8_t>((w00 * p00.g + w10 * p10.g + w01 * p01.g + w11 * p11.g + 32768) >> 16),
                         static_cast<std::uint8_t>((w00 * p00.b + w10 * p10.b + w01 * p01.b + w11 * p11.b + 32768) >> 16)};
        if (!seen) continue;
        if (!depth_apart) {
          depth_out[u] = depth_in[static_cast<std::size_t>(y + (fb >= 0.5f)) * w + x + (fa >= 0.5f)];
          continue;
        }
        // The depth's own lookup: its row's instant is depth_offset later, shifted by the camera's move
        // over that time as the colour's is over the readout.
        float dx = depth_left.x() + (u - i * kGridStep) * depth_step.x(), dy = depth_left.y() + (u - i * kGridStep) * depth_step.y();
        if (!(dx >= 0.0f && dy >= 0.0f && dx <= max_x && dy <= max_y)) continue;
        if (translating) {
          const float z = depth_in[static_cast<std::size_t>(dy + 0.5f) * w + static_cast<std::size_t>(dx + 0.5f)];
          if (isValidDepth(z)) {
            const float seconds = depth_offset + readout * (dy / h - 0.5f);
            const float x_ideal = (u - cx) / fx;
            dx -= fx * seconds * (velocity.x() - x_ideal * velocity.z()) / z;
            dy -= fy * seconds * (velocity.y() - y_ideal * velocity.z()) / z;
            if (!(dx >= 0.0f && dy >= 0.0f && dx <= max_x && dy <= max_y)) continue;
          }
        }
        depth_out[u] = depth_in[static_cast<std::size_t>(dy + 0.5f) * w + static_cast<std::size_t>(dx + 0.5f)];
      }
    }
  }
  return out;
}

}  // namespace vocal
