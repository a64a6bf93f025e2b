#include "vocal/odometry/frame_pyramid.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "vocal/odometry/odometry_backend.h"

namespace vocal {

namespace {
int clampIndex(int i, int size) { return std::min(std::max(i, 0), size - 1); }

const Eigen::Vector3f kInvalidVector = Eigen::Vector3f::Constant(std::numeric_limits<float>::quiet_NaN());
}  // namespace

PinholeCamera pyramidLevelCamera(const PinholeCamera& camera, int level) {
  PinholeCamera out = camera;
  const double scale = std::ldexp(1.0, -level);
  out.width = camera.width >> level;
  out.height = camera.height >> level;
  out.fx = camera.fx * scale;
  out.fy = camera.fy * scale;
  out.cx = camera.cx * scale;
  out.cy = camera.cy * scale;
  return out;
}

Image<float> intensityFromColor(const ColorImage& color) {
  Image<float> intensity(color.width(), color.height());
  for (std::size_t i = 0; i < color.size(); ++i) {
    const Rgb8& p = color.pixels()[i];
    intensity.pixels()[i] = (0.299f * p.r + 0.587f * p.g + 0.114f * p.b) * (1.0f / 255.0f);
  }
  return intensity;
}

DepthImage sanitizeDepth(const DepthImage& depth, double min_depth, double max_depth) {
  DepthImage out(depth.width(), depth.height());
  for (std::size_t i = 0; i < depth.size(); ++i) {
    const float z = depth.pixels()[i];
    // NaN fails both comparisons and becomes missing.
    out.pixels()[i] = (z >= min_depth && z <= max_depth) ? z : 0.0f;
  }
  return out;
}

DepthImage downsampleDepth(const DepthImage& depth, double sigma) {
  DepthImage out(depth.width() / 2, depth.height() / 2);
  const float limit = static_cast<float>(3.0 * sigma);
  for (int y = 0; y < out.height(); ++y) {
    for (int x = 0; x < out.width(); ++x) {
      const float centre = depth(2 * x, 2 * y);
      if (!(centre > 0.0f)) continue;
      float sum = 0.0f;
      int count = 0;
      for (int dy = -2; dy <= 2; ++dy) {
        for (int dx = -2; dx <= 2; ++dx) {
          const int sx = 2 * x + dx, sy = 2 * y + dy;
          if (sx < 0 || sy < 0 || sx >= depth.width() || sy >= depth.height()) continue;
          const float d = depth(sx, sy);
          if (d > 0.0f && std::fabs(d - centre) < limit) {
            sum += d;
            ++count;
          }
        }
      }
      out(x, y) = sum / count;
    }
  }
  return out;
}

Image<float> downsampleIntensity(const Image<float>& intensity) {
  static const float kWeights[5] = {1.0f / 16, 4.0f / 16, 6.0f / 16, 4.0f / 16, 1.0f / 16};
  Image<float> out(intensity.width() / 2, intensity.height() / 2);
  for (int y = 0; y < out.height(); ++y) {
    for (int x = 0; x < out.width(); ++x) {
      float sum = 0.0f;
      for (int dy = -2; dy <= 2; ++dy) {
        const int sy = clampIndex(2 * y + dy, intensity.height());
        for (int dx = -2; dx <= 2; ++dx) {
          sum += kWeights[dy + 2] * kWeights[dx + 2] * intensity(clampIndex(2 * x + dx, intensity.width()), sy);
        }
      }
      out(x, y) = sum;
    }
  }
  return out;
}

namespace {
void computeGradients(const Image<float>& I, Image<float>* gx, Image<float>* gy) {
  *gx = Image<float>(I.width(), I.height());
  *gy = Image<float>(I.width(), I.height());
  const int w = I.width(), h = I.height();
  for (int y = 0; y < h; ++y) {
    const int ym = clampIndex(y - 1, h), yp = clampIndex(y + 1, h);
    for (int x = 0; x < w; ++x) {
      const int xm = clampIndex(x - 1, w), xp = clampIndex(x + 1, w);
      (*gx)(x, y) = ((I(xp, ym) - I(xm, ym)) + 2.0f * (I(xp, y) - I(xm, y)) + (I(xp, yp) - I(xm, yp))) * 0.125f;
      (*gy)(x, y) = ((I(xm, yp) - I(xm, ym)) + 2.0f * (I(x, yp) - I(x, ym)) + (I(xp, yp) - I(xp, ym))) * 0.125f;
    }
  }
}

void computeVertices(const DepthImage& depth, const PinholeCamera& camera, Image<Eigen::Vector3f>* vertices) {
  *vertices = Image<Eigen::Vector3f>(depth.width(), depth.height(), kInvalidVector);
  const float fx_inv = static_cast<float>(1.0 / camera.fx), fy_inv = static_cast<float>(1.0 / camera.fy);
  const float cx = static_cast<float>(camera.cx), cy = static_cast<float>(camera.cy);
  for (int y = 0; y < depth.height(); ++y) {
    for (int x = 0; x < depth.width(); ++x) {
      const float z = depth(x, y);
      if (z > 0.0f) (*vertices)(x, y) = Eigen::Vector3f((x - cx) * fx_inv * z, (y - cy) * fy_inv * z, z);
    }
  }
}

void computeNormals(const Image<Eigen::Vector3f>& vertices, Image<Eigen::Vector3f>* normals) {
  *normals = Image<Eigen::Vector3f>(vertices.width(), vertices.height(), kInvalidVector);
  for (int y = 0; y + 1 < vertices.height(); ++y) {
    for (int x = 0; x + 1 < vertices.width(); ++x) {
      const Eigen::Vector3f& v = vertices(x, y);
      const Eigen::Vector3f& right = vertices(x + 1, y);
      const Eigen::Vector3f& down = vertices(x, y + 1);
      if (std::isnan(v.z()) || std::isnan(right.z()) || std::isnan(down.z())) continue;
      // (down - v) x (right - v) points towards the camera for a surface facing it.
      const Eigen::Vector3f n = (down - v).cross(right - v);
      const float length = n.norm();
      if (length > 0.0f) (*normals)(x, y) = n / length;
    }
  }
}
}  // namespace

DepthImage smoothDepth(const DepthImage& depth, int radius, float factor) {
  // Same as cl_kernels/odometry.cl smooth_depth. Averages inverse depth, which is affine in the pixel
  // coordinates on a plane, so planes stay exactly planar.
  DepthImage out(depth.width(), depth.height());
  for (int y = 0; y < depth.height(); ++y) {
    for (int x = 0; x < depth.width(); ++x) {
      const float c = depth(x, y);
      if (!(c > 0.0f)) continue;
      const float limit = factor * c * c;
      // A window symmetric about the pixel (shrunk at the image border) averages to its centre value.
      const int r = std::min({radius, x, y, depth.width() - 1 - x, depth.height() - 1 - y});
      float sum = 0.0f;
      int count = 0;
      for (int dy = -r; dy <= r; ++dy) {
        for (int dx = -r; dx <= r; ++dx) {
          const float d = depth(x + dx, y + dy);
          if (d > 0.0f && std::fabs(d - c) < limit) {
            sum += 1.0f / d;
            ++count;
          }
        }
      }
      out(x, y) = count / sum;
    }
  }
  return out;
}

FramePyramid buildFramePyramid(const RgbdFrame& frame, const PinholeCamera& camera, const OdometryConfig& config) {
  FramePyramid pyramid(config.levels);
  for (int level = 0; level < config.levels; ++level) {
    PyramidLevel& l = pyramid[level];
    l.camera = pyramidLevelCamera(camera, level);
    if (level == 0) {
      l.depth = sanitizeDepth(frame.depth, config.min_depth, config.max_depth);
      l.intensity = intensityFromColor(frame.color);
    } else {
      l.depth = downsampleDepth(pyramid[level - 1].depth, config.depth_pyramid_sigma);
      l.intensity = downsampleIntensity(pyramid[level - 1].intensity);
    }
    computeGradients(l.intensity, &l.gradient_x, &l.gradient_y);
    computeVertices(l.depth, l.camera, &l.vertices);
    if (level == 0 && config.depth_smoothing_radius > 0) {
      // Normals from smoothed depth (sensor noise and disparity steps make raw-depth normals poor);
      // the points themselves stay raw, so smoothing adds no bias to the residuals.
      Image<Eigen::Vector3f> smoothed_vertices;
      computeVertices(smoothDepth(l.depth, config.depth_smoothing_radius, static_cast<float>(config.depth_smoothing_factor)),
                      l.camera, &smoothed_vertices);
      computeNormals(smoothed_vertices, &l.normals);
    } else {
      computeNormals(l.vertices, &l.normals);
    }
  }
  return pyramid;
}

}  // namespace vocal
