#include "vocal/core/lens_distortion.h"

#include <algorithm>
#include <cmath>

#include <Eigen/LU>

#include "vocal/core/errors.h"
#include "vocal/core/pinhole_camera.h"

namespace vocal {

namespace {
std::size_t coefficientCount(DistortionModel model) {
  switch (model) {
    case DistortionModel::kPlumbBob: return 5;
    case DistortionModel::kRationalPolynomial: return 8;
    case DistortionModel::kEquidistant: return 4;
    case DistortionModel::kNone: return 0;
  }
  return 0;
}
}  // namespace

bool operator==(const LensDistortion& a, const LensDistortion& b) {
  return a.model == b.model && a.coefficients == b.coefficients;
}

std::string distortionModelName(DistortionModel model) {
  switch (model) {
    case DistortionModel::kPlumbBob: return "plumb_bob";
    case DistortionModel::kRationalPolynomial: return "rational_polynomial";
    case DistortionModel::kEquidistant: return "equidistant";
    case DistortionModel::kNone: return "";
  }
  return "";
}

Eigen::Vector2d projectThroughLens(const PinholeCamera& camera, const LensDistortion& lens, const Eigen::Vector3d& point) {
  const Eigen::Vector2d distorted = lens.distort(point.head<2>() / point.z());
  return {camera.fx * distorted.x() + camera.cx, camera.fy * distorted.y() + camera.cy};
}

LensDistortion LensDistortion::fromCameraInfo(const std::string& model, const std::vector<double>& d,
                                              const std::string& what) {
  LensDistortion distortion;
  if (std::all_of(d.begin(), d.end(), [](double k) { return k == 0.0; })) return distortion;  // none
  if (model == "plumb_bob") {
    distortion.model = DistortionModel::kPlumbBob;
  } else if (model == "rational_polynomial") {
    distortion.model = DistortionModel::kRationalPolynomial;
  } else if (model == "equidistant" || model == "fisheye") {
    distortion.model = DistortionModel::kEquidistant;
  } else {
    throw InputError(what + ": distortion_model '" + model +
                     "' is not supported (plumb_bob, rational_polynomial or equidistant)");
  }
  for (double k : d)
    if (!std::isfinite(k)) throw InputError(what + ": D has a coefficient that is not finite");
  const std::size_t expected = coefficientCount(distortion.model);
  // plumb_bob with 4 coefficients (k3 left out) is common: k3 = 0.
  if (distortion.model == DistortionModel::kPlumbBob && d.size() == 4) {
    distortion.coefficients = d;
    distortion.coefficients.push_back(0.0);
    return distortion;
  }
  if (d.size() != expected) {
    throw InputError(what + ": distortion_model " + model + " takes " + std::to_string(expected) + " coefficients, D has " +
                     std::to_string(d.size()));
  }
  distortion.coefficients = d;
  return distortion;
}

Eigen::Vector2d LensDistortion::distort(const Eigen::Vector2d& ideal) const { return distortNormalised(*this, ideal); }

Eigen::Matrix2d LensDistortion::jacobian(const Eigen::Vector2d& ideal) const {
  if (isNone()) return Eigen::Matrix2d::Identity();
  // Central differences: the models are smooth, and one code path serves all of them.
  constexpr double h = 1e-7;
  Eigen::Matrix2d J;
  for (int i = 0; i < 2; ++i) {
    Eigen::Vector2d step = Eigen::Vector2d::Zero();
    step[i] = h;
    J.col(i) = (distort(ideal + step) - distort(ideal - step)) / (2.0 * h);
  }
  return J;
}

Eigen::Vector2d LensDistortion::undistort(const Eigen::Vector2d& distorted, const Eigen::Vector2d& start) const {
  if (isNone()) return distorted;
  Eigen::Vector2d ideal = start;
  for (int iteration = 0; iteration < 50; ++iteration) {
    const Eigen::Vector2d error = distort(ideal) - distorted;
    if (error.norm() < 1e-14) break;
    ideal -= jacobian(ideal).partialPivLu().solve(error);
  }
  return ideal;
}

}  // namespace vocal
