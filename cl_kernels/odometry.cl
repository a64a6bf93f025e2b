// OpenCL C 1.2 kernels of the ICP + DVO odometry, one kernel per stage (as ElasticFusion / ICPCUDA):
// preprocessing into per-level maps, then one pass per system that builds each pixel's row and reduces
// the rows of a work-group in local memory. The host adds the per-group partial sums (in double) and
// solves the 6x6 system. src/odometry/cpu_backend.cpp is the reference of the same math.
//
// Images are row-major float buffers; vertex and normal maps are float4 (w unused), NaN = invalid;
// depth 0 = missing.

#define REDUCTION_VALUES 29

__kernel void intensity_from_rgb(__global const uchar* rgb, __global float* intensity, int pixels) {
  const int i = get_global_id(0);
  if (i >= pixels) return;
  intensity[i] = (0.299f * rgb[3 * i] + 0.587f * rgb[3 * i + 1] + 0.114f * rgb[3 * i + 2]) * (1.0f / 255.0f);
}

__kernel void sanitize_depth(__global const float* input, __global float* depth, float min_depth, float max_depth,
                             int pixels) {
  const int i = get_global_id(0);
  if (i >= pixels) return;
  const float z = input[i];
  depth[i] = (z >= min_depth && z <= max_depth) ? z : 0.0f;
}

// Averages the inverse depth of neighbours within factor * z^2 of the centre: removes sensor noise
// and quantisation steps without blurring across depth edges, and keeps planes planar (inverse depth
// is affine in the pixel coordinates on a plane).
__kernel void smooth_depth(__global const float* input, __global float* output, int width, int height, int radius,
                           float factor) {
  const int x = get_global_id(0), y = get_global_id(1);
  if (x >= width || y >= height) return;
  const float c = input[y * width + x];
  if (!(c > 0.0f)) {
    output[y * width + x] = 0.0f;
    return;
  }
  const float limit = factor * c * c;
  // A window symmetric about the pixel (shrunk at the image border) averages to its centre value.
  const int r = min(min(radius, min(x, y)), min(width - 1 - x, height - 1 - y));
  float sum = 0.0f;
  int count = 0;
  for (int dy = -r; dy <= r; ++dy) {
    for (int dx = -r; dx <= r; ++dx) {
      const float d = input[(y + dy) * width + x + dx];
      if (d > 0.0f && fabs(d - c) < limit) {
        sum += 1.0f / d;
        ++count;
      }
    }
  }
  output[y * width + x] = count / sum;
}

// 5x5 average of the neighbours within `limit` of the centre sample (2x, 2y).
__kernel void downsample_depth(__global const float* input, int width, int height, __global float* output,
                               int out_width, int out_height, float limit) {
  const int x = get_global_id(0), y = get_global_id(1);
  if (x >= out_width || y >= out_height) return;
  const float centre = input[2 * y * width + 2 * x];
  if (!(centre > 0.0f)) {
    output[y * out_width + x] = 0.0f;
    return;
  }
  float sum = 0.0f;
  int count = 0;
  for (int dy = -2; dy <= 2; ++dy) {
    for (int dx = -2; dx <= 2; ++dx) {
      const int sx = 2 * x + dx, sy = 2 * y + dy;
      if (sx < 0 || sy < 0 || sx >= width || sy >= height) continue;
      const float d = input[sy * width + sx];
      if (d > 0.0f && fabs(d - centre) < limit) {
        sum += d;
        ++count;
      }
    }
  }
  output[y * out_width + x] = sum / count;
}

// 5x5 Gaussian [1 4 6 4 1]/16 centred on (2x, 2y), borders clamped.
__kernel void downsample_intensity(__global const float* input, int width, int height, __global float* output,
                                   int out_width, int out_height) {
  const int x = get_global_id(0), y = get_global_id(1);
  if (x >= out_width || y >= out_height) return;
  const float weights[5] = {1.0f / 16, 4.0f / 16, 6.0f / 16, 4.0f / 16, 1.0f / 16};
  float sum = 0.0f;
  for (int dy = -2; dy <= 2; ++dy) {
    const int sy = clamp(2 * y + dy, 0, height - 1);
    for (int dx = -2; dx <= 2; ++dx) {
      const int sx = clamp(2 * x + dx, 0, width - 1);
      sum += weights[dy + 2] * weights[dx + 2] * input[sy * width + sx];
    }
  }
  output[y * out_width + x] = sum;
}

// Sobel / 8: intensity change per pixel.
__kernel void gradients(__global const float* I, int width, int height, __global float* gx, __global float* gy) {
  const int x = get_global_id(0), y = get_global_id(1);
  if (x >= width || y >= height) return;
  const int xm = max(x - 1, 0), xp = min(x + 1, width - 1);
  const int ym = max(y - 1, 0), yp = min(y + 1, height - 1);
  gx[y * width + x] = ((I[ym * width + xp] - I[ym * width + xm]) + 2.0f * (I[y * width + xp] - I[y * width + xm]) +
                       (I[yp * width + xp] - I[yp * width + xm])) * 0.125f;
  gy[y * width + x] = ((I[yp * width + xm] - I[ym * width + xm]) + 2.0f * (I[yp * width + x] - I[ym * width + x]) +
                       (I[yp * width + xp] - I[ym * width + xp])) * 0.125f;
}

__kernel void vertex_map(__global const float* depth, int width, int height, float fx_inv, float fy_inv, float cx,
                         float cy, __global float4* vertices) {
  const int x = get_global_id(0), y = get_global_id(1);
  if (x >= width || y >= height) return;
  const float z = depth[y * width + x];
  vertices[y * width + x] =
      z > 0.0f ? (float4)((x - cx) * fx_inv * z, (y - cy) * fy_inv * z, z, 0.0f) : (float4)(NAN, NAN, NAN, 0.0f);
}

__kernel void normal_map(__global const float4* vertices, int width, int height, __global float4* normals) {
  const int x = get_global_id(0), y = get_global_id(1);
  if (x >= width || y >= height) return;
  float4 n = (float4)(NAN, NAN, NAN, 0.0f);
  if (x + 1 < width && y + 1 < height) {
    const float3 v = vertices[y * width + x].xyz;
    const float3 right = vertices[y * width + x + 1].xyz;
    const float3 down = vertices[(y + 1) * width + x].xyz;
    if (!isnan(v.z) && !isnan(right.z) && !isnan(down.z)) {
      // (down - v) x (right - v) points towards the camera for a surface facing it.
      const float3 c = cross(down - v, right - v);
      const float length = sqrt(dot(c, c));
      if (length > 0.0f) n = (float4)(c / length, 0.0f);
    }
  }
  normals[y * width + x] = n;
}

// Adds one row (Jacobian J, residual r, weight w) to a private accumulator in the 29-value layout;
// `residual_weight` weights the squared residual (the row's noise weight, or 1 for a robust weight).
inline void accumulate_row(float* sums, const float J[6], float r, float w, float residual_weight) {
  int k = 0;
  for (int i = 0; i < 6; ++i) {
    for (int j = i; j < 6; ++j) sums[k++] += w * J[i] * J[j];
  }
  for (int i = 0; i < 6; ++i) sums[k++] -= w * r * J[i];
  sums[k++] += residual_weight * r * r;
  sums[k] += 1.0f;
}

// Tree reduction of every work-item's accumulator; work-item 0 writes the group's partial sums.
inline void reduce_group(const float* sums, __local float* scratch, __global float* partials) {
  const int lid = get_local_id(0), size = get_local_size(0);
  for (int k = 0; k < REDUCTION_VALUES; ++k) scratch[k * size + lid] = sums[k];
  barrier(CLK_LOCAL_MEM_FENCE);
  for (int stride = size / 2; stride > 0; stride >>= 1) {
    if (lid < stride) {
      for (int k = 0; k < REDUCTION_VALUES; ++k) scratch[k * size + lid] += scratch[k * size + lid + stride];
    }
    barrier(CLK_LOCAL_MEM_FENCE);
  }
  if (lid == 0) {
    for (int k = 0; k < REDUCTION_VALUES; ++k) partials[get_group_id(0) * REDUCTION_VALUES + k] = scratch[k * size];
  }
}

inline float3 transform_point(__constant const float* pose, float3 p) {
  // pose: row-major 3x3 rotation, then translation.
  return (float3)(pose[0] * p.x + pose[1] * p.y + pose[2] * p.z + pose[9],
                  pose[3] * p.x + pose[4] * p.y + pose[5] * p.z + pose[10],
                  pose[6] * p.x + pose[7] * p.y + pose[8] * p.z + pose[11]);
}

inline float3 rotate_vector(__constant const float* pose, float3 n) {
  return (float3)(pose[0] * n.x + pose[1] * n.y + pose[2] * n.z, pose[3] * n.x + pose[4] * n.y + pose[5] * n.z,
                  pose[6] * n.x + pose[7] * n.y + pose[8] * n.z);
}

// Point-to-plane ICP with projective data association; camera = (fx, fy, cx, cy) of the level.
// depth_noise = (2 floor^2, quadratic^2, the variance at 1 m) of DepthNoiseModel: each pair weighted by
// the inverse variance of its residual.
__kernel void icp_rows(__global const float4* cur_vertices, __global const float4* cur_normals,
                       __global const float4* ref_vertices, __global const float4* ref_normals, int width, int height,
                       __constant const float* pose, float4 camera, float max_distance, float min_cos,
                       float4 depth_noise, __local float* scratch, __global float* partials) {
  float sums[REDUCTION_VALUES];
  for (int k = 0; k < REDUCTION_VALUES; ++k) sums[k] = 0.0f;
  const int pixels = width * height;
  for (int i = get_global_id(0); i < pixels; i += get_global_size(0)) {
    const float3 vc = cur_vertices[i].xyz;
    const float3 nc = cur_normals[i].xyz;
    if (isnan(vc.z) || isnan(nc.z)) continue;
    const float3 p = transform_point(pose, vc);
    if (!(p.z > 0.0f)) continue;
    const int u = (int)floor(camera.x * p.x / p.z + camera.z + 0.5f);
    const int v = (int)floor(camera.y * p.y / p.z + camera.w + 0.5f);
    if (u < 0 || v < 0 || u >= width || v >= height) continue;
    const float3 vr = ref_vertices[v * width + u].xyz;
    const float3 nr = ref_normals[v * width + u].xyz;
    if (isnan(vr.z) || isnan(nr.z)) continue;
    const float3 d = p - vr;
    if (sqrt(dot(d, d)) > max_distance || dot(rotate_vector(pose, nc), nr) < min_cos) continue;
    const float3 pxn = cross(p, nr);
    const float J[6] = {nr.x, nr.y, nr.z, pxn.x, pxn.y, pxn.z};
    const float za = p.z * p.z, zb = vr.z * vr.z;
    const float w = depth_noise.z / (depth_noise.x + depth_noise.y * (za * za + zb * zb));
    accumulate_row(sums, J, dot(nr, d), w, w);
  }
  reduce_group(sums, scratch, partials);
}

inline float bilinear(__global const float* image, int width, float u, float v) {
  const int x = (int)u, y = (int)v;
  const float a = u - x, b = v - y;
  return (1 - b) * ((1 - a) * image[y * width + x] + a * image[y * width + x + 1]) +
         b * ((1 - a) * image[(y + 1) * width + x] + a * image[(y + 1) * width + x + 1]);
}

// Dense photometric residuals: current pixels warped with their depth into the reference image.
// limits = (max depth, max depth difference, min gradient, Huber threshold); brightness = (gain, bias):
// the current intensity as the reference sees it.
__kernel void dvo_rows(__global const float4* cur_vertices, __global const float* cur_intensity,
                       __global const float* ref_depth, __global const float* ref_intensity,
                       __global const float* ref_gx, __global const float* ref_gy, int width, int height,
                       __constant const float* pose, float4 camera, float4 limits, float2 brightness,
                       __local float* scratch,
                       __global float* partials) {
  float sums[REDUCTION_VALUES];
  for (int k = 0; k < REDUCTION_VALUES; ++k) sums[k] = 0.0f;
  const int pixels = width * height;
  for (int i = get_global_id(0); i < pixels; i += get_global_size(0)) {
    const float3 vc = cur_vertices[i].xyz;
    if (isnan(vc.z) || vc.z > limits.x) continue;
    const float3 p = transform_point(pose, vc);
    if (!(p.z > 0.0f)) continue;
    const float qu = camera.x * p.x / p.z + camera.z, qv = camera.y * p.y / p.z + camera.w;
    if (!(qu >= 0.0f && qv >= 0.0f && qu < width - 1 && qv < height - 1)) continue;
    const float zr = ref_depth[(int)(qv + 0.5f) * width + (int)(qu + 0.5f)];
    if (!(zr > 0.0f) || zr > limits.x || fabs(zr - p.z) > limits.y) continue;
    const float gx = bilinear(ref_gx, width, qu, qv), gy = bilinear(ref_gy, width, qu, qv);
    if (gx * gx + gy * gy < limits.z * limits.z) continue;
    const float r = bilinear(ref_intensity, width, qu, qv) - (brightness.x * cur_intensity[i] + brightness.y);
    const float z_inv = 1.0f / p.z;
    const float3 a = (float3)(gx * camera.x * z_inv, gy * camera.y * z_inv,
                              -(gx * camera.x * p.x + gy * camera.y * p.y) * z_inv * z_inv);
    const float3 pxa = cross(p, a);
    const float J[6] = {a.x, a.y, a.z, pxa.x, pxa.y, pxa.z};
    const float abs_r = fabs(r);
    accumulate_row(sums, J, r, abs_r <= limits.w ? 1.0f : limits.w / abs_r, 1.0f);
  }
  reduce_group(sums, scratch, partials);
}
