// The portable tracking row: scalar per pixel, branch-free, rows compacted by index and reduced in
// 8-lane float blocks (vectorised by the compiler: SSE2, AVX2 + FMA by run-time dispatch, or NEON).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <vector>

#include "tracking_row.h"
#include "vector_dispatch.h"

namespace vocal {

TrackingWarp::TrackingWarp(const Eigen::Isometry3d& reference_from_current, const PinholeCamera& camera,
                           const BrightnessTransfer& brightness)
    : fx(static_cast<float>(camera.fx)),
      fy(static_cast<float>(camera.fy)),
      cx(static_cast<float>(camera.cx)),
      cy(static_cast<float>(camera.cy)),
      gain(brightness.gain),
      bias(brightness.bias) {
  const Eigen::Matrix3f R = reference_from_current.linear().cast<float>();
  const Eigen::Vector3f translation = reference_from_current.translation().cast<float>();
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) r[3 * i + j] = R(i, j);
    t[i] = translation[i];
  }
}

namespace {
constexpr int kLanes = 8;
typedef float Lanes __attribute__((vector_size(kLanes * sizeof(float))));

// The rows of one term for one image row: Jacobians, residuals and weights of the pixels that passed,
// padded to whole blocks of lanes with zero rows (which add nothing). One per thread, grown as needed.
struct TermRows {
  std::array<std::vector<float>, 6> J;
  std::vector<float> r, w;
  int n = 0;

  void reset(int capacity) {
    const std::size_t padded = (capacity + kLanes - 1) / kLanes * kLanes + kLanes;
    if (r.size() < padded) {
      for (auto& j : J) j.resize(padded, 0.0f);
      r.resize(padded, 0.0f);
      w.resize(padded, 0.0f);
    }
    n = 0;
  }
  // Writes the row into the next slot and keeps it only when `keep` (branch-free compaction).
  void pushIf(bool keep, const float j[6], float residual, float weight) {
    for (int k = 0; k < 6; ++k) J[k][n] = j[k];
    r[n] = residual;
    w[n] = weight;
    n += keep;
  }
  void padToBlock() {
    for (int m = n; m % kLanes != 0; ++m) {
      for (auto& j : J) j[m] = 0.0f;
      r[m] = w[m] = 0.0f;
    }
  }
};

// Unaligned block load, inline (a function returning a vector would change the ABI per clone).
#define VOCAL_LOAD_LANES(lanes, pointer) std::memcpy(&(lanes), (pointer), sizeof(Lanes))

// Adds the rows to the 29 packed values (upper triangle of sum w J^T J, -sum w r J, sum r^2 - or
// sum w r^2 where w is the row's noise weight - and count): float within the row, double across rows.
VOCAL_VECTOR_CLONES
void reduceRows(const TermRows& rows, bool noise_weighted, double* packed) {
  Lanes acc[28] = {};
  for (int k = 0; k < rows.n; k += kLanes) {
    Lanes j[6], wj[6], w, r;
    VOCAL_LOAD_LANES(w, &rows.w[k]);
    VOCAL_LOAD_LANES(r, &rows.r[k]);
    for (int a = 0; a < 6; ++a) {
      VOCAL_LOAD_LANES(j[a], &rows.J[a][k]);
      wj[a] = w * j[a];
    }
    int m = 0;
    for (int a = 0; a < 6; ++a)
      for (int b = a; b < 6; ++b) acc[m++] += wj[a] * j[b];
    for (int a = 0; a < 6; ++a) acc[21 + a] -= wj[a] * r;
    acc[27] += (noise_weighted ? w * r : r) * r;
  }
  for (int m = 0; m < 28; ++m) {
    float sum = 0.0f;
    for (int l = 0; l < kLanes; ++l) sum += acc[m][l];
    packed[m] += sum;
  }
  packed[28] += rows.n;
}

// NaN goes to `low`.
inline float clampTo(float value, float low, float high) { return value > low ? std::min(value, high) : low; }

// The pass/fail tests of a pixel are data-dependent coin flips (gradient, distance, angle): they are
// computed as masks and every row is written, kept only where its mask is set, so the loop has no
// branches to mispredict. Lookups are clamped into the image so that a failing pixel still reads
// valid memory.
VOCAL_VECTOR_CLONES
void collectRows(const SoaPyramidLevel& cur, const SoaPyramidLevel& ref, const TrackingWarp& k,
                 const TrackingThresholds& th, int y, TermRows* icp, TermRows* rgb) {
  const int w = cur.width, rw = ref.width, rh = ref.height;
  const SurfaceRecord* surface = cur.surface.data() + static_cast<std::size_t>(y) * w;
  const float* intensity = cur.intensity.data() + static_cast<std::size_t>(y) * w;
  for (int x = 0; x < w; ++x) {
    const SurfaceRecord& s = surface[x];
    if (!(s.vz > 0.0f)) continue;  // NaN: no depth (holes are contiguous, so this branch is predictable)
    const float px = k.r[0] * s.vx + k.r[1] * s.vy + k.r[2] * s.vz + k.t[0];
    const float py = k.r[3] * s.vx + k.r[4] * s.vy + k.r[5] * s.vz + k.t[1];
    const float pz = k.r[6] * s.vx + k.r[7] * s.vy + k.r[8] * s.vz + k.t[2];
    if (!(pz > 0.0f)) continue;
    const float z_inv = 1.0f / pz;
    const float qu = k.fx * px * z_inv + k.cx, qv = k.fy * py * z_inv + k.cy;

    if (icp) {
      // Projective data association: the reference pixel the point falls into (clamped to one pixel
      // outside the image first, so that the conversion to int is defined for any projection).
      const int u = static_cast<int>(std::floor(clampTo(qu, -1.0f, static_cast<float>(rw)) + 0.5f));
      const int v = static_cast<int>(std::floor(clampTo(qv, -1.0f, static_cast<float>(rh)) + 0.5f));
      bool ok = (u >= 0) & (v >= 0) & (u < rw) & (v < rh) & !std::isnan(s.nz);
      const int uc = std::min(std::max(u, 0), rw - 1), vc = std::min(std::max(v, 0), rh - 1);
      const SurfaceRecord& q = ref.surface[static_cast<std::size_t>(vc) * rw + uc];
      const float dx = px - q.vx, dy = py - q.vy, dz = pz - q.vz;
      const float ncx = k.r[0] * s.nx + k.r[1] * s.ny + k.r[2] * s.nz;
      const float ncy = k.r[3] * s.nx + k.r[4] * s.ny + k.r[5] * s.nz;
      const float ncz = k.r[6] * s.nx + k.r[7] * s.ny + k.r[8] * s.nz;
      // NaN (no reference vertex or normal) fails both comparisons.
      ok &= (dx * dx + dy * dy + dz * dz <= th.max_distance_squared) & (ncx * q.nx + ncy * q.ny + ncz * q.nz >= th.min_cos);
      const float J[6] = {q.nx, q.ny, q.nz, py * q.nz - pz * q.ny, pz * q.nx - px * q.nz, px * q.ny - py * q.nx};
      icp->pushIf(ok, J, q.nx * dx + q.ny * dy + q.nz * dz, th.depth_noise.icpWeight(pz, q.vz));
    }

    if (rgb) {
      bool ok = (s.vz <= th.max_depth) & (qu >= 0.0f) & (qv >= 0.0f) & (qu < rw - 1) & (qv < rh - 1);
      const float qu_c = clampTo(qu, 0.0f, rw - 1.001f), qv_c = clampTo(qv, 0.0f, rh - 1.001f);
      const float zr = ref.photometric[static_cast<std::size_t>(qv_c + 0.5f) * rw + static_cast<std::size_t>(qu_c + 0.5f)].depth;
      ok &= (zr > 0.0f) & (zr <= th.max_depth) & (std::fabs(zr - pz) <= th.max_depth_difference);
      const int x0 = static_cast<int>(qu_c), y0 = static_cast<int>(qv_c);
      const float a = qu - x0, b = qv - y0;
      const PhotometricRecord* p0 = &ref.photometric[static_cast<std::size_t>(y0) * rw + x0];
      const PhotometricRecord* p1 = p0 + rw;
      auto bilinear = [&](float PhotometricRecord::*field) {
        return (1 - b) * ((1 - a) * p0[0].*field + a * p0[1].*field) + b * ((1 - a) * p1[0].*field + a * p1[1].*field);
      };
      const float gx = bilinear(&PhotometricRecord::gradient_x), gy = bilinear(&PhotometricRecord::gradient_y);
      ok &= gx * gx + gy * gy >= th.min_gradient_squared;
      const float r = bilinear(&PhotometricRecord::intensity) - (k.gain * intensity[x] + k.bias);
      // d r / d p of the projection, then d p / d twist = [I, -[p]x].
      const float ax = gx * k.fx * z_inv, ay = gy * k.fy * z_inv;
      const float az = -(gx * k.fx * px + gy * k.fy * py) * z_inv * z_inv;
      const float J[6] = {ax, ay, az, py * az - pz * ay, pz * ax - px * az, px * ay - py * ax};
      const float abs_r = std::fabs(r);
      rgb->pushIf(ok, J, r, abs_r <= th.huber ? 1.0f : th.huber / abs_r);
    }
  }
}
}  // namespace

void trackRowPortable(const SoaPyramidLevel& cur, const SoaPyramidLevel& ref, const TrackingWarp& warp,
                      const TrackingThresholds& thresholds, int y, double* icp_sums, double* rgb_sums) {
  thread_local TermRows icp_rows, rgb_rows;
  icp_rows.reset(cur.width);
  rgb_rows.reset(cur.width);
  collectRows(cur, ref, warp, thresholds, y, icp_sums ? &icp_rows : nullptr, rgb_sums ? &rgb_rows : nullptr);
  if (icp_sums) {
    icp_rows.padToBlock();
    reduceRows(icp_rows, true, icp_sums);
  }
  if (rgb_sums) {
    rgb_rows.padToBlock();
    reduceRows(rgb_rows, false, rgb_sums);
  }
}

}  // namespace vocal
