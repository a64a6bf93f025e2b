#pragma once
// Lens distortion as camera_info carries it (distortion_model + D), in OpenCV's conventions, applied to
// normalised image coordinates (x = X/Z, y = Y/Z): plumb_bob (k1 k2 p1 p2 k3, Brown-Conrady),
// rational_polynomial (k1 k2 p1 p2 k3 k4 k5 k6) and equidistant (k1 k2 k3 k4, OpenCV's fisheye model).
// Pixels are then fx * x' + cx, fy * y' + cy.

#include <cmath>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace vocal {

struct PinholeCamera;

enum class DistortionModel { kNone, kPlumbBob, kRationalPolynomial, kEquidistant };

struct LensDistortion {
  DistortionModel model = DistortionModel::kNone;
  std::vector<double> coefficients;  // in camera_info's order; their count fits the model

  // From camera_info's distortion_model and D. An empty D (or all zeros) is no distortion. Throws
  // InputError naming `what` for an unknown model or a coefficient count that does not fit it.
  static LensDistortion fromCameraInfo(const std::string& model, const std::vector<double>& d, const std::string& what);

  bool isNone() const { return model == DistortionModel::kNone; }
  // Ideal normalised coordinates -> distorted ones.
  Eigen::Vector2d distort(const Eigen::Vector2d& ideal) const;
  // The inverse (Newton's method, to 1e-12 within the lens's field of view), from `start` when a
  // close guess is known (a neighbouring pixel's), else from the distorted point itself.
  Eigen::Vector2d undistort(const Eigen::Vector2d& distorted) const { return undistort(distorted, distorted); }
  Eigen::Vector2d undistort(const Eigen::Vector2d& distorted, const Eigen::Vector2d& start) const;
  // d distort / d ideal at `ideal` (2x2).
  Eigen::Matrix2d jacobian(const Eigen::Vector2d& ideal) const;
};

bool operator==(const LensDistortion& a, const LensDistortion& b);

std::string distortionModelName(DistortionModel model);  // "", plumb_bob, rational_polynomial, equidistant

// LensDistortion::distort for any scalar type (Ceres's jets too: a graph that projects corners through
// the lens, camera_imu_calibration); the one implementation of the models.
template <typename T>
Eigen::Matrix<T, 2, 1> distortNormalised(const LensDistortion& lens, const Eigen::Matrix<T, 2, 1>& ideal) {
  using std::atan;
  using std::sqrt;
  const std::vector<double>& k = lens.coefficients;
  const T x = ideal.x(), y = ideal.y(), r2 = x * x + y * y;
  switch (lens.model) {
    case DistortionModel::kNone: return ideal;
    case DistortionModel::kPlumbBob:
    case DistortionModel::kRationalPolynomial: {
      T radial = T(1.0) + r2 * (T(k[0]) + r2 * (T(k[1]) + r2 * T(k[4])));
      if (lens.model == DistortionModel::kRationalPolynomial) radial /= T(1.0) + r2 * (T(k[5]) + r2 * (T(k[6]) + r2 * T(k[7])));
      const T p1 = T(k[2]), p2 = T(k[3]);
      return {x * radial + T(2.0) * p1 * x * y + p2 * (r2 + T(2.0) * x * x), y * radial + p1 * (r2 + T(2.0) * y * y) + T(2.0) * p2 * x * y};
    }
    case DistortionModel::kEquidistant: {
      if (r2 < T(1e-24)) return ideal;
      const T r = sqrt(r2);
      const T theta = atan(r), t2 = theta * theta;
      const T theta_d = theta * (T(1.0) + t2 * (T(k[0]) + t2 * (T(k[1]) + t2 * (T(k[2]) + t2 * T(k[3])))));
      return ideal * (theta_d / r);
    }
  }
  return ideal;
}

// The pixel where a camera with this lens sees a point of its frame (z > 0): fx * x' + cx, fy * y' + cy
// of the distorted normalised coordinates.
Eigen::Vector2d projectThroughLens(const PinholeCamera& camera, const LensDistortion& lens, const Eigen::Vector3d& point);

}  // namespace vocal
