#pragma once
// Pinhole camera model, ROS/OpenCV pixel convention: pixel (0,0) is the centre of the top-left pixel,
// optical frame z forward, x right, y down (REP-103).

#include <string>

#include <Eigen/Core>

namespace vocal {

struct PinholeCamera {
  int width = 640;
  int height = 480;
  double fx = 525.0;
  double fy = 525.0;
  double cx = 319.5;
  double cy = 239.5;
  // Raw depth units per metre (TUM PNGs: 5000, OpenNI millimetres: 1000).
  double depth_scale = 5000.0;

  Eigen::Vector2d project(const Eigen::Vector3d& point) const {
    return {fx * point.x() / point.z() + cx, fy * point.y() / point.z() + cy};
  }
  Eigen::Vector3d backProject(double u, double v, double depth) const {
    return {(u - cx) / fx * depth, (v - cy) / fy * depth, depth};
  }
  bool contains(double u, double v) const {
    return u >= 0.0 && v >= 0.0 && u <= width - 1.0 && v <= height - 1.0;
  }
  // The same camera for an image resized by `factor` (0.5 = one pyramid level down), keeping the
  // pixel-centre convention.
  PinholeCamera scaled(double factor) const;

  // Throws InputError naming `what` if sizes or focal lengths are not usable.
  void validate(const std::string& what) const;
};

bool operator==(const PinholeCamera& a, const PinholeCamera& b);

// The ROS 525/319.5/239.5 default, scaled to the given image size.
PinholeCamera defaultKinectCamera(int width = 640, int height = 480);

}  // namespace vocal
