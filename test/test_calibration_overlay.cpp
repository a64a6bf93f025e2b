// The calibration overlay: range points carried into a camera by an extrinsic are counted on the board
// the camera saw only when the extrinsic is right, and drawn where the camera's lens puts them.

#include <gtest/gtest.h>

#include "vocal/calibration/output/calibration_overlay.h"
#include "vocal/core/se3.h"

namespace {
constexpr double kWidth = 0.85, kHeight = 0.61;

// The board 2 m ahead of the camera, tilted; a "lidar" 0.3 m to the camera's left sees it as points on
// rings 4 cm apart, in its own frame.
struct Scene {
  Eigen::Isometry3d camera_from_board, camera_from_lidar;
  std::vector<Eigen::Vector3d> lidar_points;

  Scene() {
    camera_from_board = Eigen::Isometry3d::Identity();
    camera_from_board.linear() = Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitX()).toRotationMatrix();
    camera_from_board.translation() = Eigen::Vector3d(0.1, -0.05, 2.0);
    camera_from_lidar = Eigen::Isometry3d::Identity();
    camera_from_lidar.linear() = Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitY()).toRotationMatrix();
    camera_from_lidar.translation() = Eigen::Vector3d(-0.3, 0.02, 0.05);
    for (double y = -0.28; y <= 0.28; y += 0.04)
      for (double x = -0.42; x <= 0.42; x += 0.01)
        lidar_points.push_back(camera_from_lidar.inverse() * camera_from_board * Eigen::Vector3d(x, y, 0.0));
  }
  std::vector<Eigen::Vector3d> inCamera(const Eigen::Isometry3d& camera_from_lidar_estimate) const {
    std::vector<Eigen::Vector3d> points;
    for (const Eigen::Vector3d& p : lidar_points) points.push_back(camera_from_lidar_estimate * p);
    return points;
  }
};

Eigen::Isometry3d shifted(const Eigen::Isometry3d& pose, const Eigen::Vector3d& by) {
  Eigen::Isometry3d out = pose;
  out.translation() += by;
  return out;
}
}  // namespace

TEST(CalibrationOverlay, PointsLandOnTheBoardOnlyWithTheRightExtrinsic) {
  const Scene scene;
  const vocal::OverlayAgreement right =
      vocal::overlayAgreement(scene.inCamera(scene.camera_from_lidar), scene.camera_from_board, kWidth, kHeight);
  EXPECT_EQ(right.points, static_cast<int>(scene.lidar_points.size()));
  EXPECT_DOUBLE_EQ(right.on_board, 1.0);
  EXPECT_LT(right.plane_rms, 1e-9);
  // 10 cm sideways (along the board's width): the points beyond its edge (10 cm less the 2 cm margin of
  // 85 cm) are off the board; the plane distance barely changes.
  const vocal::OverlayAgreement sideways = vocal::overlayAgreement(
      scene.inCamera(shifted(scene.camera_from_lidar, scene.camera_from_board.linear().col(0) * 0.1)),
      scene.camera_from_board, kWidth, kHeight);
  EXPECT_NEAR(sideways.on_board, 1.0 - 0.08 / kWidth, 0.02);
  EXPECT_LT(sideways.plane_rms, 1e-9);
  // 3 cm along the board's normal: all on the board, 3 cm off its plane.
  const vocal::OverlayAgreement ahead = vocal::overlayAgreement(
      scene.inCamera(shifted(scene.camera_from_lidar, scene.camera_from_board.linear().col(2) * 0.03)),
      scene.camera_from_board, kWidth, kHeight);
  EXPECT_DOUBLE_EQ(ahead.on_board, 1.0);
  EXPECT_NEAR(ahead.plane_rms, 0.03, 1e-9);
  EXPECT_EQ(vocal::overlayAgreement({}, scene.camera_from_board, kWidth, kHeight).points, 0);
}

// Each layer's points are drawn where the fisheye projects them; a point behind the camera is not drawn.
TEST(CalibrationOverlay, DrawsPointsWhereTheLensProjectsThem) {
  vocal::PinholeCamera camera;  // 640 x 480
  camera.fx = camera.fy = 300.0;
  const vocal::LensDistortion fisheye =
      vocal::LensDistortion::fromCameraInfo("equidistant", {-0.013, 0.021, -0.011, 0.0021}, "camera_info");
  const vocal::ColorImage grey(camera.width, camera.height, vocal::Rgb8{100, 100, 100});
  const vocal::Rgb8 red{255, 60, 60};
  const Eigen::Vector3d seen(0.9, 0.5, 1.0), behind(0.0, 0.0, -1.0);
  const vocal::ColorImage drawn =
      vocal::drawCalibrationOverlay(grey, camera, fisheye, {}, {{"lidar", red, {seen, behind}}}, "test");
  ASSERT_TRUE(drawn.sameSize(grey));
  const Eigen::Vector2d at = vocal::projectThroughLens(camera, fisheye, seen);
  const Eigen::Vector2d pinhole = camera.project(seen);
  ASSERT_GT((at - pinhole).norm(), 20.0);  // the lens moves it visibly: the test tells the two apart
  EXPECT_EQ(drawn(static_cast<int>(std::lround(at.x())), static_cast<int>(std::lround(at.y()))), red);
  EXPECT_EQ(drawn(static_cast<int>(std::lround(pinhole.x())), static_cast<int>(std::lround(pinhole.y()))), grey(0, 0));
  // Behind the camera, the image centre (where z = -1 would wrap to) stays as it was.
  EXPECT_EQ(drawn(320, 240), grey(320, 240));
}

// Each overlay scaled to the thumbnail width with its label strip under it, placed left to right in rows.
TEST(CalibrationOverlay, ContactSheetPlacesEveryThumbnailInItsCell) {
  const vocal::Rgb8 red{255, 0, 0}, blue{0, 0, 255}, grey{40, 40, 40};
  const vocal::ColorImage wide_red(640, 480, red), tall_blue(300, 400, blue);
  const vocal::ColorImage red_thumbnail = vocal::labelledThumbnail(wide_red, 160, "pose 0, camera0");
  EXPECT_EQ(red_thumbnail.width(), 160);
  EXPECT_EQ(red_thumbnail.height(), 120 + 18);  // the aspect kept, an 18-pixel label strip
  EXPECT_EQ(red_thumbnail(80, 60), red);
  const vocal::ColorImage blue_thumbnail = vocal::labelledThumbnail(tall_blue, 160, "pose 0, camera1");
  EXPECT_EQ(blue_thumbnail.height(), 213 + 18);
  const vocal::ColorImage sheet = vocal::contactSheet({red_thumbnail, blue_thumbnail, {}, red_thumbnail}, 2);
  // Two columns, two rows of the largest cell (160 x 231).
  ASSERT_EQ(sheet.width(), 320);
  ASSERT_EQ(sheet.height(), 2 * 231);
  EXPECT_EQ(sheet(80, 60), red);                 // first row, first column
  EXPECT_EQ(sheet(160 + 80, 100), blue);         // first row, second column
  EXPECT_EQ(sheet(80, 231 + 60), grey);          // an empty image: its cell stays empty
  EXPECT_EQ(sheet(160 + 80, 231 + 60), red);     // second row, second column
  EXPECT_EQ(sheet(80, 200), grey);               // below the shorter thumbnail in its cell
  EXPECT_TRUE(vocal::contactSheet({}, 3).empty());
}
