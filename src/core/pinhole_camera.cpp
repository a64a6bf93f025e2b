#include "vocal/core/pinhole_camera.h"

#include <cmath>
#include <sstream>

#include "vocal/core/errors.h"

namespace vocal {

PinholeCamera PinholeCamera::scaled(double factor) const {
  PinholeCamera out = *this;
  out.width = static_cast<int>(std::lround(width * factor));
  out.height = static_cast<int>(std::lround(height * factor));
  out.fx = fx * factor;
  out.fy = fy * factor;
  out.cx = (cx + 0.5) * factor - 0.5;
  out.cy = (cy + 0.5) * factor - 0.5;
  return out;
}

void PinholeCamera::validate(const std::string& what) const {
  std::ostringstream problem;
  if (width <= 0 || height <= 0) {
    problem << "image size " << width << "x" << height << " is not positive";
  } else if (!(std::isfinite(fx) && std::isfinite(fy) && fx > 0.0 && fy > 0.0)) {
    problem << "focal lengths fx=" << fx << " fy=" << fy << " must be finite and positive";
  } else if (!(std::isfinite(cx) && std::isfinite(cy))) {
    problem << "principal point cx=" << cx << " cy=" << cy << " is not finite";
  } else if (!(std::isfinite(depth_scale) && depth_scale > 0.0)) {
    problem << "depth_scale " << depth_scale << " must be finite and positive";
  } else {
    return;
  }
  throw InputError(what + ": " + problem.str());
}

bool operator==(const PinholeCamera& a, const PinholeCamera& b) {
  return a.width == b.width && a.height == b.height && a.fx == b.fx && a.fy == b.fy &&
         a.cx == b.cx && a.cy == b.cy && a.depth_scale == b.depth_scale;
}

PinholeCamera defaultKinectCamera(int width, int height) {
  const PinholeCamera vga;
  const double sx = static_cast<double>(width) / vga.width;
  const double sy = static_cast<double>(height) / vga.height;
  PinholeCamera camera = vga;
  camera.width = width;
  camera.height = height;
  camera.fx = vga.fx * sx;
  camera.fy = vga.fy * sy;
  camera.cx = (vga.cx + 0.5) * sx - 0.5;
  camera.cy = (vga.cy + 0.5) * sy - 0.5;
  return camera;
}

}  // namespace vocal
