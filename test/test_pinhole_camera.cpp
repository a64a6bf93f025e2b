#include <gtest/gtest.h>

#include "test_support.h"

#include <cstdio>
#include <fstream>
#include <string>

#include "vocal/core/camera_yaml.h"
#include "vocal/core/errors.h"
#include "vocal/core/pinhole_camera.h"
#include "vocal/core/rgbd_frame.h"

using vocal::PinholeCamera;

TEST(PinholeCamera, ProjectInvertsBackProject) {
  const PinholeCamera camera = vocal::defaultKinectCamera();
  for (double u : {0.0, 100.25, 639.0}) {
    for (double v : {0.0, 240.5, 479.0}) {
      for (double z : {0.5, 2.0, 7.5}) {
        const Eigen::Vector2d uv = camera.project(camera.backProject(u, v, z));
        EXPECT_NEAR(uv.x(), u, 1e-9);
        EXPECT_NEAR(uv.y(), v, 1e-9);
      }
    }
  }
}

TEST(PinholeCamera, ScaledKeepsPixelCentres) {
  const PinholeCamera full = vocal::defaultKinectCamera();
  const PinholeCamera half = full.scaled(0.5);
  EXPECT_EQ(half.width, 320);
  EXPECT_EQ(half.height, 240);
  // The centre of 2x2 full-resolution pixels (0.5, 0.5) is the centre of half-resolution pixel (0, 0).
  const Eigen::Vector3d point = full.backProject(0.5, 0.5, 3.0);
  const Eigen::Vector2d uv = half.project(point);
  EXPECT_NEAR(uv.x(), 0.0, 1e-12);
  EXPECT_NEAR(uv.y(), 0.0, 1e-12);
  EXPECT_EQ(vocal::defaultKinectCamera(320, 240), half);
}

TEST(PinholeCamera, ValidateNamesTheProblem) {
  PinholeCamera camera;
  camera.fx = 0.0;
  EXPECT_EQ(vocal_test::inputErrorOf([&] { camera.validate("rgb/camera_info"); }),
            "rgb/camera_info: focal lengths fx=0 fy=525 must be finite and positive");
  camera = PinholeCamera();
  camera.width = 0;
  EXPECT_THROW(camera.validate("x"), vocal::InputError);
  EXPECT_NO_THROW(PinholeCamera().validate("x"));
}

TEST(CameraYaml, RoundTripsExactly) {
  PinholeCamera camera = vocal::defaultKinectCamera(320, 240);
  camera.fx = 517.3 / 3.0;  // not representable in few digits
  camera.depth_scale = 1000.0;
  const std::string path = ::testing::TempDir() + "/camera_roundtrip.yaml";
  vocal::writeCameraYaml(path, camera, "test_camera");
  EXPECT_EQ(vocal::readCameraYaml(path), camera);
}

TEST(CameraYaml, MissingKeyIsNamed) {
  const std::string path = ::testing::TempDir() + "/camera_missing.yaml";
  std::ofstream(path) << "image_width: 640\nimage_height: 480\n";
  EXPECT_EQ(vocal_test::inputErrorOf([&] { vocal::readCameraYaml(path); }),
            path + ": missing key 'camera_matrix'");
  // Found by fuzzing: a file that is not a map (or a camera_matrix that is not) escaped as a yaml-cpp exception.
  std::ofstream(path) << "- image_width\n";
  EXPECT_EQ(vocal_test::inputErrorOf([&] { vocal::readCameraYaml(path); }),
            path + ": expected a map of camera_info keys (image_width, camera_matrix, ...)");
  std::ofstream(path) << "image_width: 640\nimage_height: 480\ncamera_matrix: [1, 2]\n";
  EXPECT_EQ(vocal_test::inputErrorOf([&] { vocal::readCameraYaml(path); }),
            path + ": camera_matrix must be a map with rows, cols and data");
}

TEST(RgbdFrame, SizeMismatchIsAnError) {
  vocal::RgbdFrame frame;
  frame.color = vocal::ColorImage(640, 480);
  frame.depth = vocal::DepthImage(320, 240);
  EXPECT_EQ(vocal_test::inputErrorOf([&] { frame.validate("frame 7"); }),
            "frame 7: colour image is 640x480 but depth image is 320x240 (depth must be registered to colour)");
}
