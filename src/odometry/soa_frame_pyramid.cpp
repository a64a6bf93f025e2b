#include "vocal/odometry/soa_frame_pyramid.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "vocal/core/worker_pool.h"
#include "vocal/odometry/odometry_backend.h"
#include "vector_dispatch.h"

namespace vocal {

namespace {
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
// Work handed to a thread at a time: rows of an image, or pixels of a per-pixel loop. Small enough that
// a thread the OS leaves waiting holds up little, large enough that claiming one costs nothing.
constexpr int kRowsPerBlock = 4;
constexpr int kPixelsPerBlock = 4096;

int clampIndex(int i, int size) { return std::min(std::max(i, 0), size - 1); }

void resizeLevel(SoaPyramidLevel* l, const PinholeCamera& camera) {
  l->camera = camera;
  l->width = camera.width;
  l->height = camera.height;
  const std::size_t n = static_cast<std::size_t>(camera.width) * camera.height;
  for (std::vector<float>* plane : {&l->depth, &l->intensity, &l->gradient_x, &l->gradient_y}) plane->resize(n);
  l->surface.resize(n);
  l->photometric.resize(n);
}

// Level 0: depth outside [min, max] (and NaN) becomes missing; BT.601 intensity in [0, 1].
void sanitizeAndConvert(const RgbdFrame& frame, float min_depth, float max_depth, WorkerPool& workers, SoaPyramidLevel* l) {
  const int n = static_cast<int>(l->depth.size());
  const float* depth_in = frame.depth.data();
  const Rgb8* color = frame.color.data();
  float* depth = l->depth.data();
  float* intensity = l->intensity.data();
  workers.forEach(n, kPixelsPerBlock, [&](int i) {
    const float z = depth_in[i];
    depth[i] = (z >= min_depth && z <= max_depth) ? z : 0.0f;
    const Rgb8 p = color[i];
    intensity[i] = (0.299f * p.r + 0.587f * p.g + 0.114f * p.b) * (1.0f / 255.0f);
  });
}

// One tap of the smoothing window over a row: where the tap's depth is valid and within the centre's
// limit, its inverse depth and a count are added. Branch-free so that it vectorises; adding 0 leaves
// each pixel's sum exactly as the reference's.
VOCAL_VECTOR_CLONES
void addSmoothingTap(const float* __restrict tap_depth, const float* __restrict tap_inverse,
                     const float* __restrict centre, const float* __restrict limit, float* __restrict sum,
                     float* __restrict count, int x0, int x1) {
  for (int x = x0; x < x1; ++x) {
    const float difference = tap_depth[x] - centre[x];
    const float distance = difference < 0.0f ? -difference : difference;
    const float inside = (tap_depth[x] > 0.0f) & (distance < limit[x]) ? 1.0f : 0.0f;
    sum[x] += inside * tap_inverse[x];
    count[x] += inside;
  }
}

#ifdef VOCAL_HAND_AVX2
// One tap of an edge-preserving window in 8 lanes: where the tap's depth d is valid and within `limit`
// of the centre's, `value` is added to the sum and 1 to the count (else 0: the sums stay exactly the
// scalar loops', which skip the tap).
VOCAL_AVX2_INLINE void addTapWithin(__m256 d, __m256 value, __m256 centre, __m256 limit, __m256* sum, __m256* count) {
  const __m256 zero = _mm256_setzero_ps();
  const __m256 distance = _mm256_and_ps(_mm256_sub_ps(d, centre), _mm256_castsi256_ps(_mm256_set1_epi32(0x7fffffff)));
  const __m256 inside = _mm256_and_ps(_mm256_cmp_ps(d, zero, _CMP_GT_OQ), _mm256_cmp_ps(distance, limit, _CMP_LT_OQ));
  *sum = _mm256_add_ps(*sum, _mm256_and_ps(inside, value));
  *count = _mm256_add_ps(*count, _mm256_and_ps(inside, _mm256_set1_ps(1.0f)));
}

// One interior row of the smoothing window, pixels [x0, x1 - (x1 - x0) % 8): eight pixels at a time,
// each summing its taps in registers in the reference's order (rows, then columns), so that each
// pixel's sum is the reference's exactly; only the taps are read, nothing but the result is written
// (the tap-by-tap loop above stores and reloads every pixel's sums once per tap: 2x slower).
__attribute__((target("avx2"))) int smoothInteriorRowAvx2(const float* depth, const float* inverse, int w, int y, int radius,
                                                          float factor, int x0, int x1, float* out_row) {
  const float* centre = depth + static_cast<std::size_t>(y) * w;
  const __m256 zero = _mm256_setzero_ps(), f = _mm256_set1_ps(factor);
  int x = x0;
  for (; x + 8 <= x1; x += 8) {
    const __m256 c = _mm256_loadu_ps(centre + x);
    const __m256 limit = _mm256_mul_ps(_mm256_mul_ps(f, c), c);
    __m256 sum = zero, count = zero;
    for (int dy = -radius; dy <= radius; ++dy) {
      const std::size_t row = static_cast<std::size_t>(y + dy) * w + x;
      for (int dx = -radius; dx <= radius; ++dx) {
        addTapWithin(_mm256_loadu_ps(depth + row + dx), _mm256_loadu_ps(inverse + row + dx), c, limit, &sum, &count);
      }
    }
    // A missing centre has no taps (0 / 0): masked to 0.
    const __m256 smoothed = _mm256_and_ps(_mm256_div_ps(count, sum), _mm256_cmp_ps(c, zero, _CMP_GT_OQ));
    _mm256_storeu_ps(out_row + x, smoothed);
  }
  return x;
}
#endif

// smoothDepth of frame_pyramid.cpp: the average of the inverse depths within `radius` whose depth is
// within factor * z^2 of the centre. Interior rows: eight pixels at a time in AVX2 registers where the
// CPU has it, else tap by tap over the whole row (the inner loop over x, vectorised); each pixel sums
// in the reference's order either way.
void smoothDepth(const std::vector<float>& depth, int w, int h, int radius, float factor, WorkerPool& workers, [[maybe_unused]] bool avx2,
                 std::vector<float>* inverse_scratch, std::vector<float>* out_depth) {
  std::vector<float>& inv = *inverse_scratch;
  std::vector<float>& out = *out_depth;
  inv.resize(depth.size());
  out.resize(depth.size());
  const int n = static_cast<int>(depth.size());
  workers.forEach(n, kPixelsPerBlock, [&](int i) { inv[i] = depth[i] > 0.0f ? 1.0f / depth[i] : 0.0f; });

  auto pixelWithShrunkWindow = [&](int x, int y) {
    const float c = depth[y * w + x];
    if (!(c > 0.0f)) return 0.0f;
    const float limit = factor * c * c;
    const int r = std::min({radius, x, y, w - 1 - x, h - 1 - y});
    float sum = 0.0f;
    int count = 0;
    for (int dy = -r; dy <= r; ++dy) {
      for (int dx = -r; dx <= r; ++dx) {
        const float d = depth[(y + dy) * w + x + dx];
        if (d > 0.0f && std::fabs(d - c) < limit) {
          sum += inv[(y + dy) * w + x + dx];
          ++count;
        }
      }
    }
    return count / sum;
  };

  workers.forBlocks(h, kRowsPerBlock, [&](int, int y_begin, int y_end) {
    // Each thread's row sums, kept: a block allocates nothing.
    thread_local std::vector<float> sum, count, limit;
    for (std::vector<float>* row : {&sum, &count, &limit}) row->resize(w);
    for (int y = y_begin; y < y_end; ++y) {
      float* out_row = out.data() + static_cast<std::size_t>(y) * w;
      const float* centre = depth.data() + static_cast<std::size_t>(y) * w;
      if (y < radius || y >= h - radius || w <= 2 * radius) {
        for (int x = 0; x < w; ++x) out_row[x] = pixelWithShrunkWindow(x, y);
        continue;
      }
      for (int x = 0; x < radius; ++x) out_row[x] = pixelWithShrunkWindow(x, y);
      for (int x = w - radius; x < w; ++x) out_row[x] = pixelWithShrunkWindow(x, y);
      int x0 = radius;
      const int x1 = w - radius;
#ifdef VOCAL_HAND_AVX2
      if (avx2) x0 = smoothInteriorRowAvx2(depth.data(), inv.data(), w, y, radius, factor, x0, x1, out_row);
      if (x0 == x1) continue;
#endif
      float* __restrict s = sum.data();
      float* __restrict c = count.data();
      float* __restrict l = limit.data();
      for (int x = x0; x < x1; ++x) {
        s[x] = 0.0f;
        c[x] = 0.0f;
        l[x] = factor * centre[x] * centre[x];
      }
      for (int dy = -radius; dy <= radius; ++dy) {
        for (int dx = -radius; dx <= radius; ++dx) {
          const std::size_t offset = static_cast<std::size_t>(y + dy) * w + dx;
          addSmoothingTap(depth.data() + offset, inv.data() + offset, centre, l, s, c, x0, x1);
        }
      }
      for (int x = x0; x < x1; ++x) out_row[x] = centre[x] > 0.0f ? c[x] / s[x] : 0.0f;
    }
  });
}

#ifdef VOCAL_HAND_AVX2
// p[0], p[2], ..., p[14]: the even ones of 16 floats.
VOCAL_AVX2_INLINE __m256 evenFloats(const float* p) {
  const __m256 mixed = _mm256_shuffle_ps(_mm256_loadu_ps(p), _mm256_loadu_ps(p + 8), _MM_SHUFFLE(2, 0, 2, 0));
  return _mm256_castpd_ps(_mm256_permute4x64_pd(_mm256_castps_pd(mixed), _MM_SHUFFLE(3, 1, 2, 0)));
}

// Outputs [x, x + 8) of row y of downsampleDepth below, all of whose 5x5 windows lie inside the input:
// the same sums in the same order in 8 lanes (a tap outside the limit adds 0), so the reference's values.
__attribute__((target("avx2"))) void downsampleDepthAvx2(const float* in, int w, int x, int y, float limit, float* out) {
  const __m256 zero = _mm256_setzero_ps(), bound = _mm256_set1_ps(limit);
  const __m256 centre = evenFloats(in + static_cast<std::size_t>(2 * y) * w + 2 * x);
  __m256 sum = zero, count = zero;
  for (int dy = -2; dy <= 2; ++dy) {
    const float* row = in + static_cast<std::size_t>(2 * y + dy) * w + 2 * x;
    for (int dx = -2; dx <= 2; ++dx) {
      const __m256 d = evenFloats(row + dx);
      addTapWithin(d, d, centre, bound, &sum, &count);
    }
  }
  // A missing centre gives 0 (its lanes' 0 / 0 masked).
  _mm256_storeu_ps(out + x, _mm256_and_ps(_mm256_div_ps(sum, count), _mm256_cmp_ps(centre, zero, _CMP_GT_OQ)));
}
#endif

// downsampleDepth of frame_pyramid.cpp: 5x5 average of the neighbours within 3 sigma of the centre.
void downsampleDepth(const SoaPyramidLevel& in, float sigma, WorkerPool& workers, [[maybe_unused]] bool avx2, SoaPyramidLevel* out) {
  const float limit = 3.0f * sigma;
  const int w = in.width, h = in.height;
  auto pixel = [&](int x, int y) {
    const float centre = in.depth[2 * y * w + 2 * x];
    if (!(centre > 0.0f)) return 0.0f;
    float sum = 0.0f;
    int count = 0;
    for (int dy = -2; dy <= 2; ++dy) {
      const int sy = 2 * y + dy;
      if (sy < 0 || sy >= h) continue;
      for (int dx = -2; dx <= 2; ++dx) {
        const int sx = 2 * x + dx;
        if (sx < 0 || sx >= w) continue;
        const float d = in.depth[sy * w + sx];
        if (d > 0.0f && std::fabs(d - centre) < limit) {
          sum += d;
          ++count;
        }
      }
    }
    return sum / count;
  };
  workers.forEach(out->height, kRowsPerBlock, [&](int y) {
    float* out_row = out->depth.data() + static_cast<std::size_t>(y) * out->width;
    int x = 0;
#ifdef VOCAL_HAND_AVX2
    if (avx2 && 2 * y - 2 >= 0 && 2 * y + 2 < h) {
      // From x = 1 (the window's left edge inside), 8 at a time while the last load (16 floats from
      // 2 x + 2) stays inside the row.
      for (; x < 1 && x < out->width; ++x) out_row[x] = pixel(x, y);
      for (; x + 8 <= out->width && 2 * x + 17 < w; x += 8) downsampleDepthAvx2(in.depth.data(), w, x, y, limit, out_row);
    }
#endif
    for (; x < out->width; ++x) out_row[x] = pixel(x, y);
  });
}

// downsampleIntensity of frame_pyramid.cpp: 5x5 binomial blur, then every second pixel.
void downsampleIntensity(const SoaPyramidLevel& in, WorkerPool& workers, SoaPyramidLevel* out) {
  static const float kWeights[5] = {1.0f / 16, 4.0f / 16, 6.0f / 16, 4.0f / 16, 1.0f / 16};
  const int w = in.width, h = in.height;
  workers.forEach(out->height, kRowsPerBlock, [&](int y) {
    for (int x = 0; x < out->width; ++x) {
      float sum = 0.0f;
      for (int dy = -2; dy <= 2; ++dy) {
        const int sy = clampIndex(2 * y + dy, h);
        for (int dx = -2; dx <= 2; ++dx) {
          sum += kWeights[dy + 2] * kWeights[dx + 2] * in.intensity[sy * w + clampIndex(2 * x + dx, w)];
        }
      }
      out->intensity[y * out->width + x] = sum;
    }
  });
}

// Sobel / 8 with clamped borders, as computeGradients of frame_pyramid.cpp.
void gradients(WorkerPool& workers, SoaPyramidLevel* l) {
  const int w = l->width, h = l->height;
  const float* I = l->intensity.data();
  workers.forEach(h, kRowsPerBlock, [&](int y) {
    const float* up = I + clampIndex(y - 1, h) * w;
    const float* row = I + y * w;
    const float* down = I + clampIndex(y + 1, h) * w;
    float* gx = l->gradient_x.data() + y * w;
    float* gy = l->gradient_y.data() + y * w;
    auto at = [&](int x) {
      const int xm = clampIndex(x - 1, w), xp = clampIndex(x + 1, w);
      gx[x] = ((up[xp] - up[xm]) + 2.0f * (row[xp] - row[xm]) + (down[xp] - down[xm])) * 0.125f;
      gy[x] = ((down[xm] - up[xm]) + 2.0f * (down[x] - up[x]) + (down[xp] - up[xp])) * 0.125f;
    };
    at(0);
    for (int x = 1; x + 1 < w; ++x) {
      gx[x] = ((up[x + 1] - up[x - 1]) + 2.0f * (row[x + 1] - row[x - 1]) + (down[x + 1] - down[x - 1])) * 0.125f;
      gy[x] = ((down[x - 1] - up[x - 1]) + 2.0f * (down[x] - up[x]) + (down[x + 1] - up[x + 1])) * 0.125f;
    }
    if (w > 1) at(w - 1);
  });
}

#ifdef VOCAL_HAND_AVX2
// A vertex (u z, v z, z) where z > 0, else NaN; returns where it is valid.
VOCAL_AVX2_INLINE __m256 vertexAvx2(__m256 z, __m256 u, __m256 v, __m256* x, __m256* y, __m256* zz) {
  const __m256 valid = _mm256_cmp_ps(z, _mm256_setzero_ps(), _CMP_GT_OQ), nan = _mm256_set1_ps(kNaN);
  *x = _mm256_blendv_ps(nan, _mm256_mul_ps(u, z), valid);
  *y = _mm256_blendv_ps(nan, _mm256_mul_ps(v, z), valid);
  *zz = _mm256_blendv_ps(nan, z, valid);
  return valid;
}

// Pixels [x0, x0 + 8) of row y of records() below (each with a right and a lower neighbour): the same
// operations in the same order in 8 lanes (no FMA), so the records are the scalar loop's exactly.
__attribute__((target("avx2"))) void recordsAvx2(const float* depth, const float* normal_depth, int w, int x0, int y,
                                                 float fx_inv, float fy_inv, float cx, float cy, SoaPyramidLevel* l) {
  const __m256 zero = _mm256_setzero_ps(), nan = _mm256_set1_ps(kNaN);
  const __m256 lane = _mm256_setr_ps(0.0f, 1.0f, 2.0f, 3.0f, 4.0f, 5.0f, 6.0f, 7.0f);
  const __m256 x = _mm256_add_ps(_mm256_set1_ps(static_cast<float>(x0)), lane);
  const __m256 x_right = _mm256_add_ps(x, _mm256_set1_ps(1.0f));
  const __m256 u = _mm256_mul_ps(_mm256_sub_ps(x, _mm256_set1_ps(cx)), _mm256_set1_ps(fx_inv));
  const __m256 u_right = _mm256_mul_ps(_mm256_sub_ps(x_right, _mm256_set1_ps(cx)), _mm256_set1_ps(fx_inv));
  const __m256 v = _mm256_set1_ps((static_cast<float>(y) - cy) * fy_inv);
  const __m256 v_down = _mm256_set1_ps((static_cast<float>(y + 1) - cy) * fy_inv);
  const std::size_t i = static_cast<std::size_t>(y) * w + x0;
  __m256 vx, vy, vz, cx_, cy_, cz, rx, ry, rz, dx, dy, dz;
  vertexAvx2(_mm256_loadu_ps(depth + i), u, v, &vx, &vy, &vz);
  const __m256 centre_valid = vertexAvx2(_mm256_loadu_ps(normal_depth + i), u, v, &cx_, &cy_, &cz);
  const __m256 right_valid = vertexAvx2(_mm256_loadu_ps(normal_depth + i + 1), u_right, v, &rx, &ry, &rz);
  const __m256 down_valid = vertexAvx2(_mm256_loadu_ps(normal_depth + i + w), u, v_down, &dx, &dy, &dz);
  // (down - c) x (right - c), normalised where all three exist and it is not zero.
  const __m256 ax = _mm256_sub_ps(dx, cx_), ay = _mm256_sub_ps(dy, cy_), az = _mm256_sub_ps(dz, cz);
  const __m256 bx = _mm256_sub_ps(rx, cx_), by = _mm256_sub_ps(ry, cy_), bz = _mm256_sub_ps(rz, cz);
  const __m256 nx = _mm256_sub_ps(_mm256_mul_ps(ay, bz), _mm256_mul_ps(az, by));
  const __m256 ny = _mm256_sub_ps(_mm256_mul_ps(az, bx), _mm256_mul_ps(ax, bz));
  const __m256 nz = _mm256_sub_ps(_mm256_mul_ps(ax, by), _mm256_mul_ps(ay, bx));
  const __m256 length = _mm256_sqrt_ps(_mm256_add_ps(_mm256_mul_ps(nx, nx), _mm256_add_ps(_mm256_mul_ps(ny, ny), _mm256_mul_ps(nz, nz))));
  const __m256 normal = _mm256_and_ps(_mm256_and_ps(centre_valid, _mm256_and_ps(right_valid, down_valid)),
                                      _mm256_cmp_ps(length, zero, _CMP_GT_OQ));
  alignas(32) float out[6][8];
  _mm256_store_ps(out[0], vx);
  _mm256_store_ps(out[1], vy);
  _mm256_store_ps(out[2], vz);
  _mm256_store_ps(out[3], _mm256_blendv_ps(nan, _mm256_div_ps(nx, length), normal));
  _mm256_store_ps(out[4], _mm256_blendv_ps(nan, _mm256_div_ps(ny, length), normal));
  _mm256_store_ps(out[5], _mm256_blendv_ps(nan, _mm256_div_ps(nz, length), normal));
  for (int k = 0; k < 8; ++k) {
    l->surface[i + k] = {out[0][k], out[1][k], out[2][k], out[3][k], out[4][k], out[5][k]};
    l->photometric[i + k] = {l->intensity[i + k], l->gradient_x[i + k], l->gradient_y[i + k], l->depth[i + k]};
  }
}

#endif

// Vertices from `depth`, normals from `normal_depth` (the smoothed depth at level 0, else the same):
// computeVertices and computeNormals of frame_pyramid.cpp, written into the per-pixel records.
void records(const float* normal_depth, WorkerPool& workers, [[maybe_unused]] bool avx2, SoaPyramidLevel* l) {
  const int w = l->width, h = l->height;
  const float fx_inv = static_cast<float>(1.0 / l->camera.fx), fy_inv = static_cast<float>(1.0 / l->camera.fy);
  const float cx = static_cast<float>(l->camera.cx), cy = static_cast<float>(l->camera.cy);
  auto vertex = [&](const float* depth, int x, int y) {
    const float z = depth[y * w + x];
    return z > 0.0f ? Eigen::Vector3f((x - cx) * fx_inv * z, (y - cy) * fy_inv * z, z) : Eigen::Vector3f::Constant(kNaN);
  };
  workers.forEach(h, kRowsPerBlock, [&](int y) {
    int x_start = 0;
#ifdef VOCAL_HAND_AVX2
    if (avx2 && y + 1 < h) {
      // Eight at a time while each has a right neighbour; the rest (the last column's) below.
      for (; x_start + 8 < w; x_start += 8)
        recordsAvx2(l->depth.data(), normal_depth, w, x_start, y, fx_inv, fy_inv, cx, cy, l);
    }
#endif
    for (int x = x_start; x < w; ++x) {
      const int i = y * w + x;
      const Eigen::Vector3f v = vertex(l->depth.data(), x, y);
      Eigen::Vector3f n = Eigen::Vector3f::Constant(kNaN);
      if (x + 1 < w && y + 1 < h) {
        const Eigen::Vector3f c = normal_depth == l->depth.data() ? v : vertex(normal_depth, x, y);
        const Eigen::Vector3f right = vertex(normal_depth, x + 1, y), down = vertex(normal_depth, x, y + 1);
        if (!std::isnan(c.z()) && !std::isnan(right.z()) && !std::isnan(down.z())) {
          // (down - v) x (right - v) points towards the camera for a surface facing it.
          const Eigen::Vector3f cross = (down - c).cross(right - c);
          const float length = cross.norm();
          if (length > 0.0f) n = cross / length;
        }
      }
      l->surface[i] = {v.x(), v.y(), v.z(), n.x(), n.y(), n.z()};
      l->photometric[i] = {l->intensity[i], l->gradient_x[i], l->gradient_y[i], l->depth[i]};
    }
  });
}
}  // namespace

std::size_t SoaPyramidLevel::memoryBytes() const {
  return (depth.size() + intensity.size() + gradient_x.size() + gradient_y.size() + smoothed_depth.size() +
          inverse_depth.size()) * sizeof(float) +
         surface.size() * sizeof(SurfaceRecord) + photometric.size() * sizeof(PhotometricRecord);
}

void buildSoaFramePyramid(const RgbdFrame& frame, const PinholeCamera& camera, const OdometryConfig& config,
                          WorkerPool& workers, SoaFramePyramid* pyramid, bool allow_avx2, int finest_level) {
  // Each pass below takes this (its AVX2 code only compiled where the build can have it).
  const bool avx2 = allow_avx2 && handAvx2Available();
  pyramid->resize(config.levels);
  for (int level = 0; level < config.levels; ++level) {
    SoaPyramidLevel& l = (*pyramid)[level];
    resizeLevel(&l, pyramidLevelCamera(camera, level));
    if (level == 0) {
      sanitizeAndConvert(frame, static_cast<float>(config.min_depth), static_cast<float>(config.max_depth), workers, &l);
    } else {
      downsampleDepth((*pyramid)[level - 1], static_cast<float>(config.depth_pyramid_sigma), workers, avx2, &l);
      downsampleIntensity((*pyramid)[level - 1], workers, &l);
    }
    if (level < finest_level) continue;  // not tracked here: only what the next level is made from
    gradients(workers, &l);
    const float* normal_depth = l.depth.data();
    if (level == 0 && config.depth_smoothing_radius > 0) {
      // Normals from smoothed depth, points raw (see buildFramePyramid).
      smoothDepth(l.depth, l.width, l.height, config.depth_smoothing_radius,
                  static_cast<float>(config.depth_smoothing_factor), workers, avx2, &l.inverse_depth, &l.smoothed_depth);
      normal_depth = l.smoothed_depth.data();
    }
    records(normal_depth, workers, avx2, &l);
  }
}

}  // namespace vocal
