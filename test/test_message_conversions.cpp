// ROS messages -> core types (what the nodelets receive), without a ROS master: supported encodings
// convert exactly, everything else is refused with the topic and the problem named.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

#include <opencv2/imgcodecs.hpp>

#include "test_support.h"
#include "vocal/core/voxel_cloud_map.h"
#include "vocal/nodelets/message_conversions.h"
#include "vocal/nodelets/parameter_yaml.h"
#include "vocal/odometry/odometry_config_yaml.h"

namespace {
sensor_msgs::Image imageMsg(const std::string& encoding, int width, int height, int bytes_per_pixel) {
  sensor_msgs::Image msg;
  msg.encoding = encoding;
  msg.width = width;
  msg.height = height;
  msg.step = width * bytes_per_pixel + 4;  // padded rows, as some drivers send
  msg.data.assign(static_cast<std::size_t>(msg.step) * height, 0);
  return msg;
}
}  // namespace

TEST(MessageConversions, ColourEncodingsConvertToRgb) {
  sensor_msgs::Image bgr = imageMsg("bgr8", 3, 2, 3);
  const std::uint8_t pixel[] = {10, 20, 30};  // b, g, r
  std::memcpy(&bgr.data[bgr.step + 3], pixel, 3);  // pixel (1, 1)
  const vocal::ColorImage from_bgr = vocal::fromColorImage(bgr, "/cam/image");
  EXPECT_EQ(from_bgr(1, 1), (vocal::Rgb8{30, 20, 10}));
  EXPECT_EQ(from_bgr(0, 0), (vocal::Rgb8{0, 0, 0}));

  sensor_msgs::Image mono = imageMsg("mono8", 3, 2, 1);
  mono.data[mono.step + 2] = 77;
  EXPECT_EQ(vocal::fromColorImage(mono, "/cam/image")(2, 1), (vocal::Rgb8{77, 77, 77}));

  const vocal::ColorImage original(4, 3, vocal::Rgb8{1, 2, 3});
  EXPECT_EQ(vocal::fromColorImage(vocal::toRgb8Image(original, "f", ros::Time(1)), "/x").pixels(), original.pixels());
}

TEST(MessageConversions, DepthInMillimetresOrMetresWithMissingValuesAsZero) {
  sensor_msgs::Image mm = imageMsg("16UC1", 2, 2, 2);
  const std::uint16_t raw = 1234;
  std::memcpy(&mm.data[mm.step + 2], &raw, 2);  // pixel (1, 1)
  const vocal::DepthImage from_mm = vocal::fromDepthImage(mm, "/depth");
  EXPECT_FLOAT_EQ(from_mm(1, 1), 1.234f);
  EXPECT_EQ(from_mm(0, 0), 0.0f);

  sensor_msgs::Image metres = imageMsg("32FC1", 3, 1, 4);
  const float values[] = {2.5f, std::numeric_limits<float>::quiet_NaN(), -1.0f};
  std::memcpy(metres.data.data(), values, sizeof(values));
  const vocal::DepthImage from_m = vocal::fromDepthImage(metres, "/depth");
  EXPECT_EQ(from_m(0, 0), 2.5f);
  EXPECT_EQ(from_m(1, 0), 0.0f) << "NaN depth is missing";
  EXPECT_EQ(from_m(2, 0), 0.0f) << "negative depth is missing";
}

TEST(MessageConversions, BadMessagesNameTheTopicAndTheProblem) {
  using vocal_test::inputErrorOf;
  EXPECT_EQ(inputErrorOf([] { vocal::fromColorImage(imageMsg("16UC1", 2, 2, 2), "/cam/image"); }),
            "/cam/image: encoding '16UC1' is not a colour image (rgb8, bgr8, rgba8, bgra8, mono8, mono16, bayer_rggb8, bayer_bggr8, "
            "bayer_gbrg8, bayer_grbg8, yuv422, yuv422_yuy2)");
  EXPECT_EQ(inputErrorOf([] { vocal::fromDepthImage(imageMsg("rgb8", 2, 2, 3), "/depth"); }),
            "/depth: encoding 'rgb8' is not a depth image (16UC1 millimetres or 32FC1 metres)");
  sensor_msgs::Image short_data = imageMsg("rgb8", 4, 4, 3);
  short_data.data.resize(10);
  EXPECT_EQ(inputErrorOf([&] { vocal::fromColorImage(short_data, "/cam/image"); }),
            "/cam/image: data holds 10 bytes, 4 rows of step 16 need 64");
  sensor_msgs::Image short_step = imageMsg("32FC1", 4, 4, 4);
  short_step.step = 8;
  EXPECT_EQ(inputErrorOf([&] { vocal::fromDepthImage(short_step, "/depth"); }),
            "/depth: step 8 is shorter than a row of 4 32FC1 pixels");
  EXPECT_EQ(inputErrorOf([] { vocal::fromColorImage(imageMsg("rgb8", 0, 0, 3), "/cam/image"); }),
            "/cam/image: image is empty (0x0)");

  sensor_msgs::CameraInfo info = vocal::toCameraInfo(vocal::defaultKinectCamera(), "f", ros::Time(1));
  EXPECT_EQ(vocal::fromCameraInfo(info, "/info").fx, 525.0);
  // The lens: camera_info's distortion_model and D.
  EXPECT_TRUE(vocal::lensDistortionFromCameraInfo(info, "/info").isNone());
  info.distortion_model = "equidistant";
  info.D = {-0.013, 0.021, -0.011, 0.0021};
  const vocal::LensDistortion fisheye = vocal::lensDistortionFromCameraInfo(info, "/info");
  EXPECT_EQ(fisheye.model, vocal::DistortionModel::kEquidistant);
  EXPECT_EQ(fisheye.coefficients, info.D);
  info.D.push_back(0.1);
  EXPECT_EQ(inputErrorOf([&] { vocal::lensDistortionFromCameraInfo(info, "/info"); }),
            "/info: distortion_model equidistant takes 4 coefficients, D has 5");
  // The odometry tracks a lens it cannot read as a pinhole and says why; one it can, as read.
  std::string problem;
  EXPECT_TRUE(vocal::odometryLensFromCameraInfo(info, "/info", &problem).isNone());
  EXPECT_EQ(problem, "/info: distortion_model equidistant takes 4 coefficients, D has 5: tracking without undoing the lens");
  info.D.pop_back();
  EXPECT_EQ(vocal::odometryLensFromCameraInfo(info, "/info", &problem).model, vocal::DistortionModel::kEquidistant);
  EXPECT_EQ(problem, "");
  info.K = {};
  EXPECT_EQ(inputErrorOf([&] { vocal::fromCameraInfo(info, "/info"); }),
            "/info: K has zero focal lengths: the camera is not calibrated");

  const sensor_msgs::Image color = vocal::toRgb8Image(vocal::ColorImage(4, 3), "f", ros::Time(1));
  const sensor_msgs::Image depth = vocal::toDepth32FImage(vocal::DepthImage(2, 2), "f", ros::Time(1));
  EXPECT_EQ(inputErrorOf([&] { vocal::toRgbdFrame(color, depth, "/rgb", "/depth"); }),
            "/depth: depth is 2x2 but /rgb is 4x3 (depth must be registered to the colour image)");
}

// Found by fuzzing: width x point_step in 32 bits wrapped to 0 and passed the size check, then the
// points were read far past the data.
// image_transport's compressed images: a JPEG and a PNG decode to their pixels; a header claiming more
// than a camera gives, or bytes that are neither, are refused before decoding, naming the topic.
TEST(MessageConversions, CompressedImagesDecodeAndHugeOrGarbledOnesAreRefused) {
  cv::Mat grey(48, 64, CV_8UC1);
  for (int y = 0; y < grey.rows; ++y)
    for (int x = 0; x < grey.cols; ++x) grey.at<std::uint8_t>(y, x) = static_cast<std::uint8_t>(x * 4);
  for (const char* format : {".png", ".jpg"}) {
    sensor_msgs::CompressedImage msg;
    cv::imencode(format, grey, msg.data);
    const vocal::ColorImage image = vocal::fromCompressedColorImage(msg, "/cam/image_raw/compressed");
    ASSERT_EQ(image.width(), 64) << format;
    ASSERT_EQ(image.height(), 48) << format;
    EXPECT_NEAR(image(40, 10).g, 160, 3) << format;  // JPEG within a few grey levels
  }
  sensor_msgs::CompressedImage huge;
  cv::imencode(".png", grey, huge.data);
  huge.format = "png";
  for (const int at : {16, 20}) huge.data[at] = 0x00, huge.data[at + 1] = 0x01, huge.data[at + 2] = 0x86, huge.data[at + 3] = 0xa0;  // 100000
  EXPECT_EQ(vocal_test::inputErrorOf([&] { vocal::fromCompressedColorImage(huge, "/cam/image_raw/compressed"); }),
            "/cam/image_raw/compressed: the compressed image (format 'png') is not a JPEG or PNG of at most 64 megapixels (its header says "
            "100000x100000)");
  sensor_msgs::CompressedImage garbled;
  garbled.format = "jpeg";
  garbled.data = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10};
  EXPECT_EQ(vocal_test::inputErrorOf([&] { vocal::fromCompressedColorImage(garbled, "/cam/image_raw/compressed"); }),
            "/cam/image_raw/compressed: the compressed image (format 'jpeg') is not a JPEG or PNG of at most 64 megapixels (its header says "
            "0x0)");
  EXPECT_TRUE(vocal::isCompressedImageTopic("/cam/image_raw/compressed"));
  EXPECT_FALSE(vocal::isCompressedImageTopic("/cam/image_raw"));
}

TEST(MessageConversions, CloudWhoseSizeWrapsIn32BitsIsRefused) {
  sensor_msgs::PointCloud2 cloud = vocal::toLidarPointCloud2({Eigen::Vector3d(1, 2, 3)}, {0}, "velodyne", ros::Time(1));
  cloud.width = 65536;
  cloud.point_step = 65536;
  cloud.row_step = 16;
  EXPECT_EQ(vocal_test::inputErrorOf([&] { vocal::fromPointCloud2(cloud, "/velodyne_points"); }),
            "/velodyne_points: data holds 32 bytes, too few for 65536 points");
}

// A scan header whose angles run for more than four turns is corrupt, not a scan.
TEST(MessageConversions, ScanWhoseAnglesSpanMoreThanFourTurnsIsRefused) {
  const sensor_msgs::LaserScan scan = vocal::toLaserScan(std::vector<float>(100, 1.0f), 0.0, 1.0, 10.0, "laser", ros::Time(1));
  EXPECT_EQ(vocal_test::inputErrorOf([&] { vocal::fromLaserScan(scan, "/scan"); }),
            "/scan: angle_min 0.000000 and 100 beams of angle_increment 1.000000 span more than four turns");
  EXPECT_EQ(vocal::fromLaserScan(vocal::toLaserScan(std::vector<float>(10, 1.0f), 0.0, 1.0, 10.0, "laser", ros::Time(1)), "/scan").size(),
            10u);
}

TEST(MessageConversions, PointCloudCarriesPositionsAndPackedColour) {
  const std::vector<vocal::ColoredPoint> points = {{Eigen::Vector3f(1, 2, 3), vocal::Rgb8{255, 128, 1}}};
  const sensor_msgs::PointCloud2 cloud = vocal::toPointCloud2(points, "odom", ros::Time(5));
  ASSERT_EQ(cloud.width, 1u);
  ASSERT_EQ(cloud.fields.size(), 4u);
  EXPECT_EQ(cloud.fields[3].name, "rgb");
  float xyz[3];
  std::uint32_t rgb = 0;
  std::memcpy(xyz, cloud.data.data(), 12);
  std::memcpy(&rgb, cloud.data.data() + cloud.fields[3].offset, 4);
  EXPECT_EQ(xyz[2], 3.0f);
  EXPECT_EQ(rgb, 0xFF8001u);
}

// The layout a Velodyne driver publishes (x y z, padding, intensity, ring in 32-byte points) reads back.
TEST(MessageConversions, LidarCloudHasAVelodyneDriversLayoutAndReadsBack) {
  const std::vector<Eigen::Vector3d> points = {{1.5, -0.25, 0.125}, {-3.0, 2.0, -0.5}};
  const sensor_msgs::PointCloud2 cloud = vocal::toLidarPointCloud2(points, {3, 15}, "velodyne", ros::Time(5));
  ASSERT_EQ(cloud.fields.size(), 5u);
  EXPECT_EQ(cloud.point_step, 32u);
  EXPECT_EQ(cloud.fields[4].name, "ring");
  EXPECT_EQ(cloud.fields[4].datatype, sensor_msgs::PointField::UINT16);
  std::uint16_t ring = 0;
  std::memcpy(&ring, cloud.data.data() + cloud.point_step + cloud.fields[4].offset, 2);
  EXPECT_EQ(ring, 15);
  std::vector<int> rings = {7};
  const std::vector<Eigen::Vector3d> read = vocal::fromPointCloud2(cloud, "/velodyne_points", &rings);
  ASSERT_EQ(read.size(), 2u);
  EXPECT_EQ(read[0], points[0]);
  EXPECT_EQ(read[1], points[1]);
  EXPECT_EQ(rings, (std::vector<int>{3, 15})) << "the driver's ring field, as written";
  // An Ouster driver's ring is a uint8 (other drivers: uint16, int32): read all the same; a cloud without
  // the field gives no rings.
  sensor_msgs::PointCloud2 ouster = cloud;
  ouster.fields[4].datatype = sensor_msgs::PointField::UINT8;
  vocal::fromPointCloud2(ouster, "/os_cloud_node/points", &rings);
  EXPECT_EQ(rings, (std::vector<int>{3, 15}));  // little-endian: the uint16's low byte
  ouster.fields.pop_back();
  vocal::fromPointCloud2(ouster, "/os_cloud_node/points", &rings);
  EXPECT_TRUE(rings.empty());
  // Without rings (a scanning laser's driver), the cloud has no ring field.
  const sensor_msgs::PointCloud2 scanner = vocal::toLidarPointCloud2(points, {}, "scanner", ros::Time(5));
  ASSERT_EQ(scanner.fields.size(), 4u);
  EXPECT_EQ(scanner.fields[3].name, "intensity");
  EXPECT_EQ(vocal::fromPointCloud2(scanner, "/scanner/points", &rings), points);
  EXPECT_TRUE(rings.empty());
}

namespace {
// A raw image message of `encoding`, `bytes` bytes per pixel, rows padded to `step`, each pixel from `pixel(x, y, bytes out)`.
template <typename Pixel>
sensor_msgs::Image rawImage(const std::string& encoding, int width, int height, int bytes, int step, Pixel pixel) {
  sensor_msgs::Image msg;
  msg.encoding = encoding;
  msg.width = width, msg.height = height, msg.step = step;
  msg.data.assign(static_cast<std::size_t>(step) * height, 0);
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) pixel(x, y, msg.data.data() + static_cast<std::size_t>(y) * step + static_cast<std::size_t>(x) * bytes);
  return msg;
}
}  // namespace

// What machine-vision and USB cameras publish on image_raw: a Bayer mosaic (each pixel one colour of its
// 2 x 2 cell, named by the cell's first row), YUV 4:2:2 and 12-bit mono in 16 bits, read as the colours
// the scene had; a mosaic read with the wrong pattern swaps red and blue (what the test tells apart).
TEST(MessageConversions, RawCameraEncodingsReadAsTheirColours) {
  const vocal::Rgb8 colour{200, 90, 20};  // a flat orange scene
  const auto channel = [&](char c) { return c == 'r' ? colour.r : c == 'g' ? colour.g : colour.b; };
  for (const std::string pattern : {"rggb", "bggr", "gbrg", "grbg"}) {
    const sensor_msgs::Image mosaic = rawImage("bayer_" + pattern + "8", 8, 6, 1, 10, [&](int x, int y, std::uint8_t* p) {
      *p = channel(pattern[(y % 2) * 2 + x % 2]);
    });
    const vocal::ColorImage image = vocal::fromColorImage(mosaic, "/camera/image_raw");
    ASSERT_EQ(image.width(), 8);
    ASSERT_EQ(image.height(), 6);
    const vocal::Rgb8 centre = image(4, 3);
    EXPECT_NEAR(centre.r, colour.r, 2) << pattern;
    EXPECT_NEAR(centre.g, colour.g, 2) << pattern;
    EXPECT_NEAR(centre.b, colour.b, 2) << pattern;
  }
  // YUV 4:2:2 of the same colour as a camera writes it (BT.601, video range: Y 16-235, U and V 16-240),
  // U and V shared by each pair of pixels.
  const auto byte = [](double v) { return static_cast<std::uint8_t>(std::lround(std::clamp(v, 0.0, 255.0))); };
  const double r = colour.r, g = colour.g, b = colour.b;
  const std::uint8_t Y = byte(16.0 + (65.481 * r + 128.553 * g + 24.966 * b) / 255.0),
                     U = byte(128.0 + (-37.797 * r - 74.203 * g + 112.0 * b) / 255.0),
                     V = byte(128.0 + (112.0 * r - 93.786 * g - 18.214 * b) / 255.0);
  for (const std::string encoding : {"yuv422", "yuv422_yuy2"}) {
    const bool uyvy = encoding == "yuv422";
    const sensor_msgs::Image packed = rawImage(encoding, 8, 6, 2, 16, [&](int x, int, std::uint8_t* p) {
      p[uyvy ? 1 : 0] = Y;
      p[uyvy ? 0 : 1] = x % 2 == 0 ? U : V;
    });
    const vocal::Rgb8 centre = vocal::fromColorImage(packed, "/usb_cam/image_raw")(3, 2);
    EXPECT_NEAR(centre.r, colour.r, 3) << encoding;
    EXPECT_NEAR(centre.g, colour.g, 3) << encoding;
    EXPECT_NEAR(centre.b, colour.b, 3) << encoding;
  }
  // 12-bit mono in 16 bits: the brightest pixel (4095) reads 255, half of it 127 or 128.
  const sensor_msgs::Image mono16 = rawImage("mono16", 4, 2, 2, 8, [](int x, int, std::uint8_t* p) {
    const std::uint16_t v = x == 0 ? 4095 : 2047;
    std::memcpy(p, &v, 2);
  });
  const vocal::ColorImage grey = vocal::fromColorImage(mono16, "/camera/image_mono");
  EXPECT_EQ(grey(0, 1).r, 255);
  EXPECT_NEAR(grey(1, 0).g, 127.5, 0.6);
  // Named: an odd width cannot hold 4:2:2 pairs, a short buffer, and what is still not an image.
  sensor_msgs::Image odd = rawImage("yuv422", 7, 2, 2, 14, [](int, int, std::uint8_t*) {});
  EXPECT_EQ(vocal_test::inputErrorOf([&] { vocal::fromColorImage(odd, "/usb_cam/image_raw"); }),
            "/usb_cam/image_raw: a yuv422 image's width 7 is odd");
  sensor_msgs::Image odd_step = rawImage("mono16", 3, 2, 2, 7, [](int, int, std::uint8_t*) {});
  EXPECT_EQ(vocal_test::inputErrorOf([&] { vocal::fromColorImage(odd_step, "/camera/image_mono"); }),
            "/camera/image_mono: a mono16 image's step 7 is odd");
  sensor_msgs::Image short_mosaic = rawImage("bayer_rggb8", 8, 6, 1, 8, [](int, int, std::uint8_t*) {});
  short_mosaic.data.resize(40);
  EXPECT_EQ(vocal_test::inputErrorOf([&] { vocal::fromColorImage(short_mosaic, "/camera/image_raw"); }),
            "/camera/image_raw: data holds 40 bytes, 6 rows of step 8 need 48");
  sensor_msgs::Image depth = rawImage("32FC1", 2, 2, 4, 8, [](int, int, std::uint8_t*) {});
  EXPECT_EQ(vocal_test::inputErrorOf([&] { vocal::fromColorImage(depth, "/camera/image_raw"); }),
            "/camera/image_raw: encoding '32FC1' is not a colour image (rgb8, bgr8, rgba8, bgra8, mono8, mono16, bayer_rggb8, "
            "bayer_bggr8, bayer_gbrg8, bayer_grbg8, yuv422, yuv422_yuy2)");
}

// An Ouster driver's organised cloud holds its no-returns as points at the origin (about 2,400 of a
// 1024 x 64 scan indoors), a velodyne_pointcloud organised one as NaN: neither is a return. Kept, the
// real OS1-64 lab's calibration took 3 minutes instead of 70 s and its ring offsets moved by 11 mm.
TEST(MessageConversions, AnOrganisedCloudsNoReturnsAreNotPoints) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<Eigen::Vector3d> organised = {
      {1.5, -0.25, 0.125}, {0.0, 0.0, 0.0}, {nan, nan, nan}, {-3.0, 2.0, -0.5}, {0.0, 0.0, 0.0}, {0.0, 0.0, 0.25}};
  const sensor_msgs::PointCloud2 cloud = vocal::toLidarPointCloud2(organised, {3, 4, 5, 15, 63, 0}, "os_sensor", ros::Time(5));
  std::vector<int> rings;
  const std::vector<Eigen::Vector3d> read = vocal::fromPointCloud2(cloud, "/os_cloud_node/points", &rings);
  EXPECT_EQ(read, (std::vector<Eigen::Vector3d>{organised[0], organised[3], organised[5]}));
  EXPECT_EQ(rings, (std::vector<int>{3, 15, 0})) << "each return keeps its own ring";
}

TEST(VoxelCloudMap, FusesViewsOfOneSurfaceIntoOnePointPerVoxel) {
  // The same 1 m x 1 m patch seen from two camera poses lands in the same voxels of the map.
  std::vector<vocal::ColoredPoint> patch;
  for (int i = 0; i < 50; ++i)
    for (int j = 0; j < 50; ++j) patch.push_back({Eigen::Vector3f(0.02f * i + 0.001f, 0.02f * j + 0.001f, 2.0f), vocal::Rgb8{100, 0, 0}});
  vocal::VoxelCloudMap map(0.04, 100000);
  map.add(patch, Eigen::Isometry3d::Identity());
  const std::size_t one_view = map.voxels();
  EXPECT_EQ(one_view, 25u * 25u);
  Eigen::Isometry3d moved = Eigen::Isometry3d::Identity();
  moved.translation() = Eigen::Vector3d(0.0, 0.0, 0.5);
  std::vector<vocal::ColoredPoint> seen_from_closer = patch;
  for (auto& p : seen_from_closer) p.position.z() -= 0.5f, p.color = vocal::Rgb8{200, 0, 0};
  map.add(seen_from_closer, moved);
  EXPECT_EQ(map.voxels(), one_view);
  for (const vocal::ColoredPoint& p : map.points()) {
    EXPECT_NEAR(p.position.z(), 2.0f, 1e-5f);
    EXPECT_EQ(p.color.r, 150);
  }
  // A budget caps memory and counts what it dropped.
  vocal::VoxelCloudMap small(0.04, 10);
  small.add(patch, Eigen::Isometry3d::Identity());
  EXPECT_EQ(small.voxels(), 10u);
  EXPECT_EQ(small.droppedPoints(), patch.size() - 10 * 4);
  // A later view elsewhere pushes out what the oldest add() put in (whole), not its own points.
  std::vector<vocal::ColoredPoint> elsewhere = patch;
  for (auto& p : elsewhere) p.position.x() += 5.0f;
  vocal::VoxelCloudMap lru(0.04, 1000);
  lru.add(patch, Eigen::Isometry3d::Identity());      // 625 voxels
  lru.add(elsewhere, Eigen::Isometry3d::Identity());  // 625 more than the budget holds
  EXPECT_EQ(lru.droppedPoints(), 0u);
  EXPECT_EQ(lru.evictedVoxels(), 625u);
  EXPECT_EQ(lru.voxels(), 625u);
  for (const vocal::ColoredPoint& p : lru.points()) EXPECT_GT(p.position.x(), 4.0f);
  EXPECT_EQ(vocal_test::inputErrorOf([] { vocal::VoxelCloudMap(0.0, 10); }),
            "voxel cloud map: voxel size 0.000000 m must be positive");
}

// A nodelet's private parameters (as rosparam loads them) go through the config file's parser: its
// own keys are ignored, odometry keys are applied, bad values are named.
TEST(NodeletParameters, OdometrySettingsFromRosParameters) {
  XmlRpc::XmlRpcValue parameters;
  parameters["frame_id"] = std::string("base_link");
  parameters["rgb_weight"] = 2.0;
  parameters["min_icp_inliers"] = 300;
  parameters["mode"] = std::string("icp");
  parameters["iterations"][0] = 4;
  parameters["iterations"][1] = 3;
  parameters["iterations"][2] = 2;
  const vocal::OdometryConfig config =
      vocal::odometryConfigFromYaml(vocal::toYaml(parameters), "parameters of /odometry", vocal::OdometryConfig{}, true);
  EXPECT_EQ(config.rgb_weight, 2.0);
  EXPECT_EQ(config.min_icp_inliers, 300);
  EXPECT_EQ(config.mode, vocal::OdometryMode::kIcp);
  EXPECT_EQ(config.iterations, (std::vector<int>{4, 3, 2}));
  EXPECT_EQ(config.max_depth, vocal::OdometryConfig{}.max_depth);

  parameters["rgb_weight"] = std::string("heavy");
  EXPECT_EQ(vocal_test::inputErrorOf([&] {
              vocal::odometryConfigFromYaml(vocal::toYaml(parameters), "parameters of /odometry", vocal::OdometryConfig{}, true);
            }).rfind("parameters of /odometry: setting 'rgb_weight' is malformed", 0),
            0u);
}

TEST(MessageConversions, AGyrosImuMessageReadsBackAndANonFiniteRateIsNamed) {
  const vocal::ImuSample sample{12.25, Eigen::Vector3d(0.1, -0.2, 0.3), Eigen::Vector3d(0.0, 0.5, 9.8)};
  sensor_msgs::Imu msg = vocal::toImuMessage(sample, "camera_imu_frame");
  EXPECT_EQ(msg.orientation_covariance[0], -1.0);
  EXPECT_NE(msg.angular_velocity_covariance[0], -1.0);  // the rates are there
  const vocal::ImuSample back = vocal::fromImuMessage(msg, "/camera/imu");
  EXPECT_DOUBLE_EQ(back.stamp, 12.25);
  EXPECT_TRUE(back.angular_velocity.isApprox(sample.angular_velocity));
  EXPECT_TRUE(back.linear_acceleration.isApprox(sample.linear_acceleration));
  msg.angular_velocity.y = std::numeric_limits<double>::quiet_NaN();
  try {
    vocal::fromImuMessage(msg, "/camera/imu");
    FAIL() << "a NaN rate was taken";
  } catch (const vocal::InputError& e) {
    EXPECT_EQ(std::string(e.what()), "/camera/imu: angular_velocity (0.1, nan, 0.3) or linear_acceleration is not finite");
  }
}
