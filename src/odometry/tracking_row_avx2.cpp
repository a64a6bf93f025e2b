// The AVX2 + FMA tracking row: 8 pixels at a time, reference records fetched with hardware gathers,
// the pass/fail tests as lane masks. A failing lane's Jacobian and residual are zeroed, so it adds
// nothing and no compaction is needed; the 28 products accumulate in registers (float) for the row.
// Only these functions are compiled for AVX2 (target attribute), so the library still loads on any
// x86-64; avx2TrackRow() hands them out only where the CPU has AVX2 and FMA.
#include "tracking_row.h"

#if defined(__GNUC__) && defined(__x86_64__)
#include <immintrin.h>

#define VOCAL_AVX2 __attribute__((target("avx2,fma")))

namespace vocal {
namespace {

constexpr int kBlock = 8;

struct RowAccumulator {
  __m256 acc[28];
  int count = 0;
};

VOCAL_AVX2 inline void clear(RowAccumulator* sums) {
  for (__m256& a : sums->acc) a = _mm256_setzero_ps();
  sums->count = 0;
}

// acc += [w J^T J (upper triangle), -w r J, r^2 (w r^2 where w is a noise weight)] per lane.
VOCAL_AVX2 inline void accumulate(RowAccumulator* sums, const __m256 J[6], __m256 r, __m256 w, __m256 ok,
                                  bool noise_weighted) {
  __m256 j[6], wj[6];
  // A failing lane (its values possibly NaN) becomes zeros.
  for (int a = 0; a < 6; ++a) j[a] = _mm256_and_ps(J[a], ok);
  r = _mm256_and_ps(r, ok);
  w = _mm256_and_ps(w, ok);
  for (int a = 0; a < 6; ++a) wj[a] = _mm256_mul_ps(w, j[a]);
  __m256* acc = sums->acc;
  int m = 0;
  for (int a = 0; a < 6; ++a)
    for (int b = a; b < 6; ++b, ++m) acc[m] = _mm256_fmadd_ps(wj[a], j[b], acc[m]);
  for (int a = 0; a < 6; ++a) acc[21 + a] = _mm256_fnmadd_ps(wj[a], r, acc[21 + a]);
  acc[27] = _mm256_fmadd_ps(noise_weighted ? _mm256_mul_ps(w, r) : r, r, acc[27]);
  sums->count += __builtin_popcount(_mm256_movemask_ps(ok));
}

VOCAL_AVX2 inline void addTo(const RowAccumulator& sums, double* packed) {
  for (int m = 0; m < 28; ++m) {
    alignas(32) float lanes[kBlock];
    _mm256_store_ps(lanes, sums.acc[m]);
    float sum = 0.0f;
    for (float lane : lanes) sum += lane;
    packed[m] += sum;
  }
  packed[28] += sums.count;
}

// value > low ? min(value, high) : low, so NaN goes to low (as clampTo in the portable row).
VOCAL_AVX2 inline __m256 clampTo(__m256 value, float low, float high) {
  const __m256 lo = _mm256_set1_ps(low);
  return _mm256_blendv_ps(lo, _mm256_min_ps(value, _mm256_set1_ps(high)), _mm256_cmp_ps(value, lo, _CMP_GT_OQ));
}

VOCAL_AVX2 inline __m256 gather(const float* base, __m256i index) { return _mm256_i32gather_ps(base, index, 4); }

// DepthNoiseModel::icpWeight of 8 pairs, the same operations.
VOCAL_AVX2 inline __m256 depthNoiseWeight(const DepthNoiseModel& noise, __m256 z_current, __m256 z_reference) {
  const __m256 a = _mm256_mul_ps(z_current, z_current), b = _mm256_mul_ps(z_reference, z_reference);
  const __m256 variance = _mm256_add_ps(_mm256_set1_ps(2.0f * noise.floor_squared),
                                        _mm256_mul_ps(_mm256_set1_ps(noise.quadratic_squared),
                                                      _mm256_add_ps(_mm256_mul_ps(a, a), _mm256_mul_ps(b, b))));
  return _mm256_div_ps(_mm256_set1_ps(noise.variance_at_one_metre), variance);
}

VOCAL_AVX2 inline __m256 mul3(const float* row, __m256 x, __m256 y, __m256 z) {
  return _mm256_fmadd_ps(_mm256_set1_ps(row[0]), x,
                         _mm256_fmadd_ps(_mm256_set1_ps(row[1]), y, _mm256_mul_ps(_mm256_set1_ps(row[2]), z)));
}

// Bilinear interpolation of one record field between the four corner records (float indices).
struct BilinearCorners {
  __m256i p00, p01, p10, p11;
  __m256 a, a1, b, b1;  // weights: a = fractional column, b = fractional row, a1 = 1 - a, b1 = 1 - b
};

VOCAL_AVX2 inline __m256 bilinear(const float* field, const BilinearCorners& c) {
  const __m256 top = _mm256_fmadd_ps(c.a1, gather(field, c.p00), _mm256_mul_ps(c.a, gather(field, c.p01)));
  const __m256 bottom = _mm256_fmadd_ps(c.a1, gather(field, c.p10), _mm256_mul_ps(c.a, gather(field, c.p11)));
  return _mm256_fmadd_ps(c.b1, top, _mm256_mul_ps(c.b, bottom));
}

VOCAL_AVX2
void trackRowAvx2(const SoaPyramidLevel& cur, const SoaPyramidLevel& ref, const TrackingWarp& k,
                  const TrackingThresholds& th, int y, double* icp_sums, double* rgb_sums) {
  const int w = cur.width, rw = ref.width, rh = ref.height;
  const float* surface = reinterpret_cast<const float*>(cur.surface.data() + static_cast<std::size_t>(y) * w);
  const float* intensity = cur.intensity.data() + static_cast<std::size_t>(y) * w;
  const float* ref_surface = reinterpret_cast<const float*>(ref.surface.data());
  const float* ref_photometric = reinterpret_cast<const float*>(ref.photometric.data());
  constexpr int kSurfaceFloats = sizeof(SurfaceRecord) / sizeof(float);
  constexpr int kPhotometricFloats = sizeof(PhotometricRecord) / sizeof(float);
  static_assert(kSurfaceFloats == 6 && kPhotometricFloats == 4, "records are packed floats");

  const __m256i lane = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
  const __m256i record_offsets = _mm256_mullo_epi32(lane, _mm256_set1_epi32(kSurfaceFloats));
  const __m256 nan = _mm256_set1_ps(__builtin_nanf(""));
  const __m256 zero = _mm256_setzero_ps(), one = _mm256_set1_ps(1.0f), half = _mm256_set1_ps(0.5f);
  const __m256 fx = _mm256_set1_ps(k.fx), fy = _mm256_set1_ps(k.fy), cx = _mm256_set1_ps(k.cx),
               cy = _mm256_set1_ps(k.cy);
  const __m256i rw_i = _mm256_set1_epi32(rw), rh_i = _mm256_set1_epi32(rh), minus_one_i = _mm256_set1_epi32(-1);
  const __m256 abs_mask = _mm256_castsi256_ps(_mm256_set1_epi32(0x7fffffff));

  RowAccumulator icp_acc, rgb_acc;
  clear(&icp_acc);
  clear(&rgb_acc);

  for (int x = 0; x < w; x += kBlock) {
    // Lanes past the row's end are masked out of the loads and read as NaN depth.
    const __m256i in_row = _mm256_cmpgt_epi32(_mm256_set1_epi32(w - x), lane);
    const __m256 in_row_ps = _mm256_castsi256_ps(in_row);
    const float* s = surface + static_cast<std::size_t>(x) * kSurfaceFloats;
    const __m256 vz = _mm256_mask_i32gather_ps(nan, s + 2, record_offsets, in_row_ps, 4);
    __m256 base = _mm256_cmp_ps(vz, zero, _CMP_GT_OQ);
    if (_mm256_movemask_ps(base) == 0) continue;  // a hole (holes are contiguous)
    const __m256 vx = _mm256_mask_i32gather_ps(zero, s + 0, record_offsets, base, 4);
    const __m256 vy = _mm256_mask_i32gather_ps(zero, s + 1, record_offsets, base, 4);
    const __m256 px = _mm256_add_ps(mul3(k.r + 0, vx, vy, vz), _mm256_set1_ps(k.t[0]));
    const __m256 py = _mm256_add_ps(mul3(k.r + 3, vx, vy, vz), _mm256_set1_ps(k.t[1]));
    const __m256 pz = _mm256_add_ps(mul3(k.r + 6, vx, vy, vz), _mm256_set1_ps(k.t[2]));
    base = _mm256_and_ps(base, _mm256_cmp_ps(pz, zero, _CMP_GT_OQ));
    if (_mm256_movemask_ps(base) == 0) continue;
    const __m256 z_inv = _mm256_div_ps(one, pz);
    const __m256 qu = _mm256_fmadd_ps(_mm256_mul_ps(fx, px), z_inv, cx);
    const __m256 qv = _mm256_fmadd_ps(_mm256_mul_ps(fy, py), z_inv, cy);

    if (icp_sums) {
      const __m256 nx = _mm256_mask_i32gather_ps(nan, s + 3, record_offsets, base, 4);
      const __m256 ny = _mm256_mask_i32gather_ps(nan, s + 4, record_offsets, base, 4);
      const __m256 nz = _mm256_mask_i32gather_ps(nan, s + 5, record_offsets, base, 4);
      // Projective association, as in the portable row: nearest reference pixel of the clamped projection.
      const __m256i u = _mm256_cvttps_epi32(
          _mm256_floor_ps(_mm256_add_ps(clampTo(qu, -1.0f, static_cast<float>(rw)), half)));
      const __m256i v = _mm256_cvttps_epi32(
          _mm256_floor_ps(_mm256_add_ps(clampTo(qv, -1.0f, static_cast<float>(rh)), half)));
      const __m256i inside = _mm256_and_si256(
          _mm256_and_si256(_mm256_cmpgt_epi32(u, minus_one_i), _mm256_cmpgt_epi32(v, minus_one_i)),
          _mm256_and_si256(_mm256_cmpgt_epi32(rw_i, u), _mm256_cmpgt_epi32(rh_i, v)));
      __m256 ok = _mm256_and_ps(_mm256_and_ps(base, _mm256_castsi256_ps(inside)), _mm256_cmp_ps(nz, nz, _CMP_ORD_Q));
      const __m256i uc = _mm256_min_epi32(_mm256_max_epi32(u, _mm256_setzero_si256()), _mm256_set1_epi32(rw - 1));
      const __m256i vc = _mm256_min_epi32(_mm256_max_epi32(v, _mm256_setzero_si256()), _mm256_set1_epi32(rh - 1));
      const __m256i q = _mm256_mullo_epi32(_mm256_add_epi32(_mm256_mullo_epi32(vc, rw_i), uc),
                                           _mm256_set1_epi32(kSurfaceFloats));
      const __m256 qvx = gather(ref_surface + 0, q), qvy = gather(ref_surface + 1, q), qvz = gather(ref_surface + 2, q);
      const __m256 qnx = gather(ref_surface + 3, q), qny = gather(ref_surface + 4, q), qnz = gather(ref_surface + 5, q);
      const __m256 dx = _mm256_sub_ps(px, qvx), dy = _mm256_sub_ps(py, qvy), dz = _mm256_sub_ps(pz, qvz);
      const __m256 ncx = mul3(k.r + 0, nx, ny, nz), ncy = mul3(k.r + 3, nx, ny, nz), ncz = mul3(k.r + 6, nx, ny, nz);
      const __m256 distance_squared = _mm256_fmadd_ps(dx, dx, _mm256_fmadd_ps(dy, dy, _mm256_mul_ps(dz, dz)));
      const __m256 cos_angle = _mm256_fmadd_ps(ncx, qnx, _mm256_fmadd_ps(ncy, qny, _mm256_mul_ps(ncz, qnz)));
      // NaN (no reference vertex or normal) fails both ordered comparisons.
      ok = _mm256_and_ps(ok, _mm256_cmp_ps(distance_squared, _mm256_set1_ps(th.max_distance_squared), _CMP_LE_OQ));
      ok = _mm256_and_ps(ok, _mm256_cmp_ps(cos_angle, _mm256_set1_ps(th.min_cos), _CMP_GE_OQ));
      const __m256 J[6] = {qnx, qny, qnz, _mm256_fmsub_ps(py, qnz, _mm256_mul_ps(pz, qny)),
                           _mm256_fmsub_ps(pz, qnx, _mm256_mul_ps(px, qnz)),
                           _mm256_fmsub_ps(px, qny, _mm256_mul_ps(py, qnx))};
      const __m256 r = _mm256_fmadd_ps(qnx, dx, _mm256_fmadd_ps(qny, dy, _mm256_mul_ps(qnz, dz)));
      accumulate(&icp_acc, J, r, depthNoiseWeight(th.depth_noise, pz, qvz), ok, true);
    }

    if (rgb_sums) {
      __m256 ok = _mm256_and_ps(base, _mm256_cmp_ps(vz, _mm256_set1_ps(th.max_depth), _CMP_LE_OQ));
      ok = _mm256_and_ps(ok, _mm256_and_ps(_mm256_cmp_ps(qu, zero, _CMP_GE_OQ), _mm256_cmp_ps(qv, zero, _CMP_GE_OQ)));
      ok = _mm256_and_ps(ok, _mm256_and_ps(_mm256_cmp_ps(qu, _mm256_set1_ps(static_cast<float>(rw - 1)), _CMP_LT_OQ),
                                           _mm256_cmp_ps(qv, _mm256_set1_ps(static_cast<float>(rh - 1)), _CMP_LT_OQ)));
      const __m256 qu_c = clampTo(qu, 0.0f, rw - 1.001f), qv_c = clampTo(qv, 0.0f, rh - 1.001f);
      // Nearest pixel's depth for the occlusion test (truncation of the non-negative +0.5: rounding).
      const __m256i nearest = _mm256_add_epi32(_mm256_mullo_epi32(_mm256_cvttps_epi32(_mm256_add_ps(qv_c, half)), rw_i),
                                               _mm256_cvttps_epi32(_mm256_add_ps(qu_c, half)));
      const __m256 zr = gather(ref_photometric + 3, _mm256_slli_epi32(nearest, 2));
      ok = _mm256_and_ps(ok, _mm256_and_ps(_mm256_cmp_ps(zr, zero, _CMP_GT_OQ),
                                           _mm256_cmp_ps(zr, _mm256_set1_ps(th.max_depth), _CMP_LE_OQ)));
      ok = _mm256_and_ps(ok, _mm256_cmp_ps(_mm256_and_ps(_mm256_sub_ps(zr, pz), abs_mask),
                                           _mm256_set1_ps(th.max_depth_difference), _CMP_LE_OQ));
      const __m256i x0 = _mm256_cvttps_epi32(qu_c), y0 = _mm256_cvttps_epi32(qv_c);
      BilinearCorners corners;
      corners.a = _mm256_sub_ps(qu, _mm256_cvtepi32_ps(x0));
      corners.b = _mm256_sub_ps(qv, _mm256_cvtepi32_ps(y0));
      corners.a1 = _mm256_sub_ps(one, corners.a);
      corners.b1 = _mm256_sub_ps(one, corners.b);
      corners.p00 = _mm256_slli_epi32(_mm256_add_epi32(_mm256_mullo_epi32(y0, rw_i), x0), 2);
      corners.p01 = _mm256_add_epi32(corners.p00, _mm256_set1_epi32(kPhotometricFloats));
      corners.p10 = _mm256_add_epi32(corners.p00, _mm256_set1_epi32(rw * kPhotometricFloats));
      corners.p11 = _mm256_add_epi32(corners.p10, _mm256_set1_epi32(kPhotometricFloats));
      const __m256 gx = bilinear(ref_photometric + 1, corners), gy = bilinear(ref_photometric + 2, corners);
      ok = _mm256_and_ps(ok, _mm256_cmp_ps(_mm256_fmadd_ps(gx, gx, _mm256_mul_ps(gy, gy)),
                                           _mm256_set1_ps(th.min_gradient_squared), _CMP_GE_OQ));
      const __m256 current = _mm256_maskload_ps(intensity + x, in_row);
      const __m256 r = _mm256_sub_ps(bilinear(ref_photometric, corners),
                                     _mm256_fmadd_ps(_mm256_set1_ps(k.gain), current, _mm256_set1_ps(k.bias)));
      // d r / d p of the projection, then d p / d twist = [I, -[p]x].
      const __m256 gfx = _mm256_mul_ps(gx, fx), gfy = _mm256_mul_ps(gy, fy);
      const __m256 ax = _mm256_mul_ps(gfx, z_inv), ay = _mm256_mul_ps(gfy, z_inv);
      const __m256 az = _mm256_mul_ps(_mm256_sub_ps(zero, _mm256_fmadd_ps(gfx, px, _mm256_mul_ps(gfy, py))),
                                      _mm256_mul_ps(z_inv, z_inv));
      const __m256 J[6] = {ax, ay, az, _mm256_fmsub_ps(py, az, _mm256_mul_ps(pz, ay)),
                           _mm256_fmsub_ps(pz, ax, _mm256_mul_ps(px, az)),
                           _mm256_fmsub_ps(px, ay, _mm256_mul_ps(py, ax))};
      // Huber weight: 1 within the threshold, threshold / |r| beyond.
      const __m256 abs_r = _mm256_and_ps(r, abs_mask), huber = _mm256_set1_ps(th.huber);
      const __m256 weight =
          _mm256_blendv_ps(_mm256_div_ps(huber, abs_r), one, _mm256_cmp_ps(abs_r, huber, _CMP_LE_OQ));
      accumulate(&rgb_acc, J, r, weight, ok, false);
    }
  }
  if (icp_sums) addTo(icp_acc, icp_sums);
  if (rgb_sums) addTo(rgb_acc, rgb_sums);
}

bool cpuHasAvx2AndFma() {
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
}

}  // namespace

TrackRowFunction avx2TrackRow() {
  static const bool available = cpuHasAvx2AndFma();
  return available ? &trackRowAvx2 : nullptr;
}

}  // namespace vocal

#else

namespace vocal {
TrackRowFunction avx2TrackRow() { return nullptr; }
}  // namespace vocal

#endif
