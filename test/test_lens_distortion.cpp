// Lens distortion models against OpenCV's own projection (projectPoints, fisheye::projectPoints), their
// inverse, and the errors for camera_info values that do not fit.

#include <gtest/gtest.h>

#include <limits>

#include <random>

#include <ceres/jet.h>
#include <opencv2/calib3d.hpp>

#include "test_support.h"
#include "vocal/core/lens_distortion.h"
#include "vocal/core/pinhole_camera.h"

namespace {
// Real magnitudes: a wide-angle lens (k1 about -0.3), a rational-polynomial model as calibrated by
// OpenCV for wide lenses, and a fisheye.
struct ModelCase {
  const char* model;
  std::vector<double> d;
  double half_fov_deg;  // points are drawn within this angle of the axis
};
const ModelCase kCases[] = {
    {"plumb_bob", {-0.30, 0.09, 0.0012, -0.0008, -0.012}, 45},
    {"rational_polynomial", {0.45, -0.08, 0.0009, 0.0004, -0.01, 0.75, 0.02, -0.02}, 50},
    {"equidistant", {-0.013, 0.021, -0.011, 0.0021}, 85},
};

std::vector<cv::Point3d> randomPoints(double half_fov_deg, std::mt19937* rng) {
  std::uniform_real_distribution<double> angle(0.0, half_fov_deg * M_PI / 180.0), azimuth(-M_PI, M_PI), range(0.5, 4.0);
  std::vector<cv::Point3d> points;
  for (int i = 0; i < 200; ++i) {
    const double a = angle(*rng), b = azimuth(*rng), r = range(*rng);
    points.emplace_back(r * std::sin(a) * std::cos(b), r * std::sin(a) * std::sin(b), r * std::cos(a));
  }
  return points;
}
}  // namespace

TEST(LensDistortion, ProjectsAsOpenCvDoesForEveryModel) {
  const vocal::PinholeCamera camera = vocal::defaultKinectCamera(1920, 1208);
  const cv::Matx33d K(camera.fx, 0, camera.cx, 0, camera.fy, camera.cy, 0, 0, 1);
  std::mt19937 rng(5);
  for (const ModelCase& c : kCases) {
    const vocal::LensDistortion distortion = vocal::LensDistortion::fromCameraInfo(c.model, c.d, "camera_info");
    EXPECT_EQ(vocal::distortionModelName(distortion.model), c.model);
    const std::vector<cv::Point3d> points = randomPoints(c.half_fov_deg, &rng);
    std::vector<cv::Point2d> expected;
    if (distortion.model == vocal::DistortionModel::kEquidistant) {
      cv::fisheye::projectPoints(points, expected, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), K, c.d);
    } else {
      cv::projectPoints(points, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), K, c.d, expected);
    }
    double worst = 0.0, worst_inverse = 0.0;
    for (std::size_t i = 0; i < points.size(); ++i) {
      const Eigen::Vector2d ideal(points[i].x / points[i].z, points[i].y / points[i].z);
      const Eigen::Vector2d distorted = distortion.distort(ideal);
      const Eigen::Vector2d pixel = vocal::projectThroughLens(camera, distortion, {points[i].x, points[i].y, points[i].z});
      worst = std::max(worst, (pixel - Eigen::Vector2d(expected[i].x, expected[i].y)).norm());
      worst_inverse = std::max(worst_inverse, (distortion.undistort(distorted) - ideal).norm());
    }
    EXPECT_LT(worst, 1e-6) << c.model << ": pixels";
    EXPECT_LT(worst_inverse, 1e-10) << c.model << ": undistort(distort(x)) - x";
    // The Jacobian against a wider finite difference.
    const Eigen::Vector2d at(0.3, -0.2);
    const Eigen::Matrix2d J = distortion.jacobian(at);
    for (int k = 0; k < 2; ++k) {
      Eigen::Vector2d step = Eigen::Vector2d::Zero();
      step[k] = 1e-5;
      EXPECT_LT((J.col(k) - (distortion.distort(at + step) - distortion.distort(at - step)) / 2e-5).norm(), 1e-6) << c.model;
    }
  }
}

// The models with Ceres's jets (a graph that projects corners through the lens): the same values, and
// derivatives that match the models' own (central differences).
TEST(LensDistortion, JetsGiveTheSameValuesAndTheModelsDerivatives) {
  std::mt19937 rng(5);
  for (const ModelCase& c : kCases) {
    const vocal::LensDistortion lens = vocal::LensDistortion::fromCameraInfo(c.model, c.d, "test");
    for (const cv::Point3d& p : randomPoints(c.half_fov_deg, &rng)) {
      const Eigen::Vector2d ideal(p.x / p.z, p.y / p.z);
      using Jet = ceres::Jet<double, 2>;
      const Eigen::Matrix<Jet, 2, 1> jets = vocal::distortNormalised<Jet>(lens, {Jet(ideal.x(), 0), Jet(ideal.y(), 1)});
      const Eigen::Vector2d plain = lens.distort(ideal);
      const Eigen::Matrix2d jacobian = lens.jacobian(ideal);
      for (int i = 0; i < 2; ++i) {
        EXPECT_NEAR(jets[i].a, plain[i], 1e-12) << c.model;
        for (int j = 0; j < 2; ++j) EXPECT_NEAR(jets[i].v[j], jacobian(i, j), 1e-5 * (1.0 + std::abs(jacobian(i, j)))) << c.model;
      }
    }
  }
}

TEST(LensDistortion, CameraInfoValuesAreCheckedAndNamed) {
  EXPECT_TRUE(vocal::LensDistortion::fromCameraInfo("plumb_bob", {0, 0, 0, 0, 0}, "x").isNone());
  EXPECT_TRUE(vocal::LensDistortion::fromCameraInfo("", {}, "x").isNone());
  const vocal::LensDistortion four = vocal::LensDistortion::fromCameraInfo("plumb_bob", {-0.2, 0.05, 0, 0}, "x");
  EXPECT_EQ(four.coefficients, (std::vector<double>{-0.2, 0.05, 0, 0, 0}));
  EXPECT_EQ(vocal_test::inputErrorOf([] { vocal::LensDistortion::fromCameraInfo("equidistant", {0.1, 0.2, 0.3}, "/cam/camera_info"); }),
            "/cam/camera_info: distortion_model equidistant takes 4 coefficients, D has 3");
  EXPECT_EQ(vocal_test::inputErrorOf([] { vocal::LensDistortion::fromCameraInfo("kannala", {0.1}, "/cam/camera_info"); }),
            "/cam/camera_info: distortion_model 'kannala' is not supported (plumb_bob, rational_polynomial or equidistant)");
  // Found by fuzzing: four plumb_bob coefficients (k3 left out) skipped the finiteness check.
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_EQ(vocal_test::inputErrorOf([&] { vocal::LensDistortion::fromCameraInfo("plumb_bob", {nan, 0, 0, 0}, "/cam/camera_info"); }),
            "/cam/camera_info: D has a coefficient that is not finite");
}
