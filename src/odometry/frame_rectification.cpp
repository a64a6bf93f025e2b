#include "vocal/odometry/frame_rectification.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Geometry>

#include "vocal/core/worker_pool.h"
#include "vector_dispatch.h"

namespace vocal {

namespace {
// Output rows a thread takes at a time.
constexpr int kRowsPerBlock = 4;

#ifdef VOCAL_HAND_AVX2
// What one row's cells share.
struct RowConstants {
  const Rgb8* colour_in;
  const float* depth_in;
  int w, h, v;
  float max_x, max_y, fx, fy, cx, cy, y_ideal, depth_offset, readout;
  Eigen::Vector3f moving, velocity;
  bool colour_translating, translating, depth_apart;
};

VOCAL_AVX2_INLINE __m256 insideImage(__m256 x, __m256 y, __m256 max_x, __m256 max_y) {
  const __m256 zero = _mm256_setzero_ps();
  return _mm256_and_ps(_mm256_and_ps(_mm256_cmp_ps(x, zero, _CMP_GE_OQ), _mm256_cmp_ps(y, zero, _CMP_GE_OQ)),
                       _mm256_and_ps(_mm256_cmp_ps(x, max_x, _CMP_LE_OQ), _mm256_cmp_ps(y, max_y, _CMP_LE_OQ)));
}

VOCAL_AVX2_INLINE __m256i nearestIndex(__m256 x, __m256 y, __m256i w) {
  const __m256 half = _mm256_set1_ps(0.5f);
  return _mm256_add_epi32(_mm256_mullo_epi32(_mm256_cvttps_epi32(_mm256_add_ps(y, half)), w),
                          _mm256_cvttps_epi32(_mm256_add_ps(x, half)));
}

VOCAL_AVX2_INLINE __m256 validDepth(__m256 z, __m256 mask) {
  return _mm256_and_ps(mask, _mm256_and_ps(_mm256_cmp_ps(z, _mm256_setzero_ps(), _CMP_GT_OQ),
                                           _mm256_cmp_ps(z, _mm256_set1_ps(1e30f), _CMP_LT_OQ)));
}

// The camera's own move over `time` (times `motion`) shifts the lookups (x, y) that are `inside` by
// (fx (t_x - x_ideal t_z), fy (t_y - y_ideal t_z)) / z at the depth z found there; `inside` is
// tested again where they moved.
VOCAL_AVX2_INLINE void shiftAlongTranslation(const RowConstants& c, __m256 time, const Eigen::Vector3f& motion, __m256 x_ideal,
                                             __m256* x, __m256* y, __m256* inside) {
  const __m256 z = _mm256_mask_i32gather_ps(_mm256_setzero_ps(), c.depth_in, nearestIndex(*x, *y, _mm256_set1_epi32(c.w)), *inside, 4);
  const __m256 valid = validDepth(z, *inside);
  const __m256 shift_x = _mm256_div_ps(_mm256_mul_ps(_mm256_mul_ps(_mm256_set1_ps(c.fx), time),
                                                     _mm256_sub_ps(_mm256_set1_ps(motion.x()), _mm256_mul_ps(x_ideal, _mm256_set1_ps(motion.z())))),
                                       z);
  const __m256 shift_y =
      _mm256_div_ps(_mm256_mul_ps(_mm256_mul_ps(_mm256_set1_ps(c.fy), time), _mm256_set1_ps(motion.y() - c.y_ideal * motion.z())), z);
  *x = _mm256_blendv_ps(*x, _mm256_sub_ps(*x, shift_x), valid);
  *y = _mm256_blendv_ps(*y, _mm256_sub_ps(*y, shift_y), valid);
  *inside = _mm256_blendv_ps(*inside, insideImage(*x, *y, _mm256_set1_ps(c.max_x), _mm256_set1_ps(c.max_y)), valid);
}

// One grid cell (8 pixels from u0) of FrameRectification::rectify's row loop, the same operations in
// the same order in 8 lanes (no FMA: the same roundings), so the output is the scalar loop's exactly;
// colour and depth are fetched with gathers.
__attribute__((target("avx2"))) void rectifyCellAvx2(const RowConstants& c, int u0, const Eigen::Vector2f& left,
                                                     const Eigen::Vector2f& step, const Eigen::Vector2f& depth_left,
                                                     const Eigen::Vector2f& depth_step, Rgb8* colour_out, float* depth_out) {
  const __m256 zero = _mm256_setzero_ps(), half = _mm256_set1_ps(0.5f);
  const __m256 max_x = _mm256_set1_ps(c.max_x), max_y = _mm256_set1_ps(c.max_y);
  const __m256i w = _mm256_set1_epi32(c.w);
  const __m256 lane = _mm256_setr_ps(0.0f, 1.0f, 2.0f, 3.0f, 4.0f, 5.0f, 6.0f, 7.0f);
  const __m256 u = _mm256_add_ps(_mm256_set1_ps(static_cast<float>(u0)), lane);
  const __m256 x_ideal = _mm256_div_ps(_mm256_sub_ps(u, _mm256_set1_ps(c.cx)), _mm256_set1_ps(c.fx));
  const __m256 height = _mm256_set1_ps(static_cast<float>(c.h));
  __m256 sx = _mm256_add_ps(_mm256_set1_ps(left.x()), _mm256_mul_ps(lane, _mm256_set1_ps(step.x())));
  __m256 sy = _mm256_add_ps(_mm256_set1_ps(left.y()), _mm256_mul_ps(lane, _mm256_set1_ps(step.y())));
  __m256 seen = insideImage(sx, sy, max_x, max_y);
  if (c.colour_translating) {
    const __m256 share = _mm256_sub_ps(_mm256_div_ps(sy, height), half);  // of the readout, after the middle row
    shiftAlongTranslation(c, share, c.moving, x_ideal, &sx, &sy, &seen);
  }
  // Outside the input: the nearest border pixel (NaN: the output pixel itself).
  const __m256 clamped_x = _mm256_min_ps(_mm256_max_ps(_mm256_blendv_ps(sx, u, _mm256_cmp_ps(sx, sx, _CMP_UNORD_Q)), zero), max_x);
  const __m256 v = _mm256_set1_ps(static_cast<float>(c.v));
  const __m256 clamped_y = _mm256_min_ps(_mm256_max_ps(_mm256_blendv_ps(sy, v, _mm256_cmp_ps(sy, sy, _CMP_UNORD_Q)), zero), max_y);
  sx = _mm256_blendv_ps(clamped_x, sx, seen);
  sy = _mm256_blendv_ps(clamped_y, sy, seen);
  const __m256i x = _mm256_min_epi32(_mm256_cvttps_epi32(sx), _mm256_set1_epi32(c.w - 2));
  const __m256i y = _mm256_min_epi32(_mm256_cvttps_epi32(sy), _mm256_set1_epi32(c.h - 2));
  const __m256 fa = _mm256_sub_ps(sx, _mm256_cvtepi32_ps(x)), fb = _mm256_sub_ps(sy, _mm256_cvtepi32_ps(y));
  const __m256 scale = _mm256_set1_ps(256.0f);
  const __m256i wa = _mm256_cvttps_epi32(_mm256_add_ps(_mm256_mul_ps(fa, scale), half));
  const __m256i wb = _mm256_cvttps_epi32(_mm256_add_ps(_mm256_mul_ps(fb, scale), half));
  const __m256i full = _mm256_set1_epi32(256);
  const __m256i w00 = _mm256_mullo_epi32(_mm256_sub_epi32(full, wa), _mm256_sub_epi32(full, wb));
  const __m256i w10 = _mm256_mullo_epi32(wa, _mm256_sub_epi32(full, wb));
  const __m256i w01 = _mm256_mullo_epi32(_mm256_sub_epi32(full, wa), wb);
  const __m256i w11 = _mm256_mullo_epi32(wa, wb);
  // Byte offsets of the four pixels' RGB, read as 32 bits each; the last one's read ends at its own
  // last byte (the image's last pixel has none after it) and is shifted down.
  const __m256i offset = _mm256_mullo_epi32(_mm256_add_epi32(_mm256_mullo_epi32(y, w), x), _mm256_set1_epi32(3));
  const int* colour = reinterpret_cast<const int*>(c.colour_in);
  const __m256i p00 = _mm256_i32gather_epi32(colour, offset, 1);
  const __m256i p10 = _mm256_i32gather_epi32(colour, _mm256_add_epi32(offset, _mm256_set1_epi32(3)), 1);
  const __m256i p01 = _mm256_i32gather_epi32(colour, _mm256_add_epi32(offset, _mm256_set1_epi32(3 * c.w)), 1);
  const __m256i p11 = _mm256_srli_epi32(_mm256_i32gather_epi32(colour, _mm256_add_epi32(offset, _mm256_set1_epi32(3 * c.w + 2)), 1), 8);
  const __m256i byte = _mm256_set1_epi32(0xff), rounding = _mm256_set1_epi32(32768);
  alignas(32) int channels[3][8];
  for (int channel = 0; channel < 3; ++channel) {
    const __m256i shift = _mm256_set1_epi32(8 * channel);
    __m256i sum = _mm256_mullo_epi32(w00, _mm256_and_si256(_mm256_srlv_epi32(p00, shift), byte));
    sum = _mm256_add_epi32(sum, _mm256_mullo_epi32(w10, _mm256_and_si256(_mm256_srlv_epi32(p10, shift), byte)));
    sum = _mm256_add_epi32(sum, _mm256_mullo_epi32(w01, _mm256_and_si256(_mm256_srlv_epi32(p01, shift), byte)));
    sum = _mm256_add_epi32(sum, _mm256_mullo_epi32(w11, _mm256_and_si256(_mm256_srlv_epi32(p11, shift), byte)));
    _mm256_store_si256(reinterpret_cast<__m256i*>(channels[channel]), _mm256_srli_epi32(_mm256_add_epi32(sum, rounding), 16));
  }
  for (int k = 0; k < 8; ++k) {
    colour_out[u0 + k] = {static_cast<std::uint8_t>(channels[0][k]), static_cast<std::uint8_t>(channels[1][k]),
                          static_cast<std::uint8_t>(channels[2][k])};
  }
  if (!c.depth_apart) {
    // The nearest of the four: a mask is -1 where the fraction is at least a half.
    const __m256i near_x = _mm256_sub_epi32(x, _mm256_castps_si256(_mm256_cmp_ps(fa, half, _CMP_GE_OQ)));
    const __m256i near_y = _mm256_sub_epi32(y, _mm256_castps_si256(_mm256_cmp_ps(fb, half, _CMP_GE_OQ)));
    const __m256 depth = _mm256_mask_i32gather_ps(zero, c.depth_in, _mm256_add_epi32(_mm256_mullo_epi32(near_y, w), near_x), seen, 4);
    _mm256_storeu_ps(depth_out + u0, depth);
    return;
  }
  __m256 dx = _mm256_add_ps(_mm256_set1_ps(depth_left.x()), _mm256_mul_ps(lane, _mm256_set1_ps(depth_step.x())));
  __m256 dy = _mm256_add_ps(_mm256_set1_ps(depth_left.y()), _mm256_mul_ps(lane, _mm256_set1_ps(depth_step.y())));
  __m256 found = _mm256_and_ps(seen, insideImage(dx, dy, max_x, max_y));
  if (c.translating) {
    const __m256 seconds =
        _mm256_add_ps(_mm256_set1_ps(c.depth_offset), _mm256_mul_ps(_mm256_set1_ps(c.readout), _mm256_sub_ps(_mm256_div_ps(dy, height), half)));
    shiftAlongTranslation(c, seconds, c.velocity, x_ideal, &dx, &dy, &found);
  }
  _mm256_storeu_ps(depth_out + u0, _mm256_mask_i32gather_ps(zero, c.depth_in, nearestIndex(dx, dy, w), found, 4));
}
#endif
}  // namespace

FrameRectification::FrameRectification(const PinholeCamera& camera, const LensDistortion& lens, double readout_seconds,
                                       double depth_time_offset, bool allow_avx2)
    : camera_(camera), lens_(lens), readout_(readout_seconds), depth_time_offset_(depth_time_offset),
      avx2_(allow_avx2 && handAvx2Available()) {}

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
                                      const Eigen::Vector3d& linear_velocity, WorkerPool* workers) const {
  WorkerPool& pool = workers ? *workers : WorkerPool::callerOnly();
  const int w = camera_.width, h = camera_.height;
  // The lookup at grid nodes every kGridStep pixels (one node past the last row and column).
  const int nodes_x = (w - 1) / kGridStep + 2, nodes_y = (h - 1) / kGridStep + 2;
  auto lookupGrid = [&](double time_offset) {
    std::vector<Eigen::Vector2f> grid(static_cast<std::size_t>(nodes_x) * nodes_y);
    pool.forEach(nodes_y, 1, [&](int j) {
      for (int i = 0; i < nodes_x; ++i)
        grid[static_cast<std::size_t>(j) * nodes_x + i] =
            sourcePixel(i * kGridStep, j * kGridStep, angular_velocity, time_offset).cast<float>();
    });
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
  pool.forEach(h, kRowsPerBlock, [&](int v) {
    // The row's lookups at the grid's columns (between its node rows), then linear along the row.
    const int j = v / kGridStep;
    const float b = static_cast<float>(v - j * kGridStep) / kGridStep;
    const Eigen::Vector2f* top = &nodes[static_cast<std::size_t>(j) * nodes_x];
    const Eigen::Vector2f* bottom = top + nodes_x;
    const Eigen::Vector2f* depth_top = depth_apart ? &depth_nodes[static_cast<std::size_t>(j) * nodes_x] : nullptr;
    Rgb8* colour_out = &out.color(0, v);
    float* depth_out = &out.depth(0, v);
    const float y_ideal = (v - cy) / fy;
#ifdef VOCAL_HAND_AVX2
    const RowConstants row{colour_in, depth_in, w, h, v, max_x, max_y, fx, fy, cx, cy, y_ideal, depth_offset, readout,
                           moving, velocity, colour_translating, translating, depth_apart};
#endif
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
#ifdef VOCAL_HAND_AVX2
      static_assert(kGridStep == 8, "a cell is one AVX2 register of pixels");
      if (avx2_ && u_end - i * kGridStep == kGridStep) {
        rectifyCellAvx2(row, i * kGridStep, left, step, depth_left, depth_step, colour_out, depth_out);
        continue;
      }
#endif
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
  });
  return out;
}

}  // namespace vocal
