#include "vocal/nodelets/message_conversions.h"

#include <algorithm>
#include <cstring>
#include <limits>

#include <cmath>
#include <sstream>
#include <utility>
#include <vector>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <sensor_msgs/image_encodings.h>
#include <tf2_eigen/tf2_eigen.h>

#include "vocal/core/errors.h"

namespace vocal {

sensor_msgs::CameraInfo toCameraInfo(const PinholeCamera& camera, const std::string& frame_id, const ros::Time& stamp,
                                     const LensDistortion& distortion) {
  sensor_msgs::CameraInfo info;
  info.header.stamp = stamp;
  info.header.frame_id = frame_id;
  info.width = camera.width;
  info.height = camera.height;
  if (distortion.isNone()) {
    info.distortion_model = "plumb_bob";
    info.D.assign(5, 0.0);
  } else {
    info.distortion_model = distortionModelName(distortion.model);
    info.D = distortion.coefficients;
  }
  info.K = {camera.fx, 0.0, camera.cx, 0.0, camera.fy, camera.cy, 0.0, 0.0, 1.0};
  info.R = {1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0};
  info.P = {camera.fx, 0.0, camera.cx, 0.0, 0.0, camera.fy, camera.cy, 0.0, 0.0, 0.0, 1.0, 0.0};
  return info;
}

namespace {
// An image message of tightly packed rows, data allocated, pixels left to fill.
sensor_msgs::Image emptyImage(int width, int height, const std::string& encoding, int bytes_per_pixel,
                              const std::string& frame_id, const ros::Time& stamp) {
  sensor_msgs::Image msg;
  msg.header.stamp = stamp;
  msg.header.frame_id = frame_id;
  msg.width = width;
  msg.height = height;
  msg.encoding = encoding;
  msg.step = bytes_per_pixel * width;
  msg.data.resize(static_cast<std::size_t>(msg.step) * msg.height);
  return msg;
}
}  // namespace

sensor_msgs::Image toRgb8Image(const ColorImage& image, const std::string& frame_id, const ros::Time& stamp) {
  sensor_msgs::Image msg = emptyImage(image.width(), image.height(), sensor_msgs::image_encodings::RGB8, 3, frame_id, stamp);
  static_assert(sizeof(Rgb8) == 3, "Rgb8 must be tightly packed");
  std::memcpy(msg.data.data(), image.data(), msg.data.size());
  return msg;
}

sensor_msgs::Image toBgr8Image(const ColorImage& image, const std::string& frame_id, const ros::Time& stamp) {
  sensor_msgs::Image msg = emptyImage(image.width(), image.height(), sensor_msgs::image_encodings::BGR8, 3, frame_id, stamp);
  for (std::size_t i = 0; i < image.size(); ++i) {
    const Rgb8& p = image.pixels()[i];
    msg.data[3 * i] = p.b, msg.data[3 * i + 1] = p.g, msg.data[3 * i + 2] = p.r;
  }
  return msg;
}

sensor_msgs::Image toMono8Image(const ColorImage& image, const std::string& frame_id, const ros::Time& stamp) {
  sensor_msgs::Image msg = emptyImage(image.width(), image.height(), sensor_msgs::image_encodings::MONO8, 1, frame_id, stamp);
  for (std::size_t i = 0; i < image.size(); ++i) msg.data[i] = luma8(image.pixels()[i]);
  return msg;
}

sensor_msgs::Image toDepth32FImage(const DepthImage& depth, const std::string& frame_id, const ros::Time& stamp) {
  sensor_msgs::Image msg =
      emptyImage(depth.width(), depth.height(), sensor_msgs::image_encodings::TYPE_32FC1, 4, frame_id, stamp);
  float* out = reinterpret_cast<float*>(msg.data.data());
  for (std::size_t i = 0; i < depth.size(); ++i) {
    out[i] = isValidDepth(depth.pixels()[i]) ? depth.pixels()[i] : std::numeric_limits<float>::quiet_NaN();
  }
  return msg;
}

sensor_msgs::Image toDepth16UImage(const DepthImage& depth, const std::string& frame_id, const ros::Time& stamp) {
  sensor_msgs::Image msg =
      emptyImage(depth.width(), depth.height(), sensor_msgs::image_encodings::TYPE_16UC1, 2, frame_id, stamp);
  std::uint16_t* out = reinterpret_cast<std::uint16_t*>(msg.data.data());
  for (std::size_t i = 0; i < depth.size(); ++i) {
    const float z = depth.pixels()[i];
    out[i] = isValidDepth(z) && z < 65.5f ? static_cast<std::uint16_t>(std::lround(z * 1000.0f)) : 0;
  }
  return msg;
}

namespace {
void addPointField(sensor_msgs::PointCloud2* msg, const char* name, std::uint32_t offset, std::uint8_t datatype) {
  sensor_msgs::PointField field;
  field.name = name;
  field.offset = offset;
  field.datatype = datatype;
  field.count = 1;
  msg->fields.push_back(field);
}
}  // namespace

sensor_msgs::PointCloud2 toPointCloud2(const std::vector<ColoredPoint>& points, const std::string& frame_id,
                                       const ros::Time& stamp) {
  sensor_msgs::PointCloud2 msg;
  msg.header.stamp = stamp;
  msg.header.frame_id = frame_id;
  msg.height = 1;
  msg.width = static_cast<std::uint32_t>(points.size());
  for (const char* name : {"x", "y", "z", "rgb"}) addPointField(&msg, name, 4 * static_cast<std::uint32_t>(msg.fields.size()), sensor_msgs::PointField::FLOAT32);
  msg.is_bigendian = false;
  msg.point_step = 16;
  msg.row_step = msg.point_step * msg.width;
  msg.is_dense = true;
  msg.data.resize(static_cast<std::size_t>(msg.row_step));
  std::uint8_t* out = msg.data.data();
  for (const ColoredPoint& p : points) {
    const std::uint32_t rgb = (std::uint32_t{p.color.r} << 16) | (std::uint32_t{p.color.g} << 8) | p.color.b;
    std::memcpy(out, p.position.data(), 12);
    std::memcpy(out + 12, &rgb, 4);
    out += msg.point_step;
  }
  return msg;
}

sensor_msgs::PointCloud2 toLidarPointCloud2(const std::vector<Eigen::Vector3d>& points, const std::vector<int>& rings,
                                            const std::string& frame_id, const ros::Time& stamp) {
  sensor_msgs::PointCloud2 msg;
  msg.header.stamp = stamp;
  msg.header.frame_id = frame_id;
  msg.height = 1;
  msg.width = static_cast<std::uint32_t>(points.size());
  // velodyne_pointcloud's PointXYZIR: x y z, 4 bytes of padding, intensity, ring, padding to 32 bytes.
  addPointField(&msg, "x", 0, sensor_msgs::PointField::FLOAT32);
  addPointField(&msg, "y", 4, sensor_msgs::PointField::FLOAT32);
  addPointField(&msg, "z", 8, sensor_msgs::PointField::FLOAT32);
  addPointField(&msg, "intensity", 16, sensor_msgs::PointField::FLOAT32);
  if (!rings.empty()) addPointField(&msg, "ring", 20, sensor_msgs::PointField::UINT16);
  msg.is_bigendian = false;
  msg.point_step = 32;
  msg.row_step = msg.point_step * msg.width;
  msg.is_dense = true;
  msg.data.assign(static_cast<std::size_t>(msg.row_step), 0);
  std::uint8_t* out = msg.data.data();
  for (std::size_t i = 0; i < points.size(); ++i, out += msg.point_step) {
    const Eigen::Vector3f p = points[i].cast<float>();
    const float intensity = 50.0f;
    const auto ring = static_cast<std::uint16_t>(i < rings.size() ? rings[i] : 0);
    std::memcpy(out, p.data(), 12);
    std::memcpy(out + 16, &intensity, 4);
    std::memcpy(out + 20, &ring, 2);
  }
  return msg;
}

geometry_msgs::TransformStamped toTransformStamped(const Eigen::Isometry3d& parent_from_child,
                                                   const std::string& parent, const std::string& child,
                                                   const ros::Time& stamp) {
  geometry_msgs::TransformStamped msg = tf2::eigenToTransform(parent_from_child);
  msg.header.stamp = stamp;
  msg.header.frame_id = parent;
  msg.child_frame_id = child;
  return msg;
}

namespace {
// The rows of `msg` hold `bytes_per_pixel` bytes per pixel: step and data must cover them.
void checkLayout(const sensor_msgs::Image& msg, std::size_t bytes_per_pixel, const std::string& what) {
  std::ostringstream problem;
  if (msg.width == 0 || msg.height == 0) {
    problem << "image is empty (" << msg.width << "x" << msg.height << ")";
  } else if (msg.step < msg.width * bytes_per_pixel) {
    problem << "step " << msg.step << " is shorter than a row of " << msg.width << " " << msg.encoding << " pixels";
  } else if (msg.data.size() < static_cast<std::size_t>(msg.step) * msg.height) {
    problem << "data holds " << msg.data.size() << " bytes, " << msg.height << " rows of step " << msg.step << " need "
            << static_cast<std::size_t>(msg.step) * msg.height;
  }
  if (!problem.str().empty()) throw InputError(what + ": " + problem.str());
}

// A camera's raw or packed image (a machine-vision camera's Bayer mosaic, a USB camera's YUV 4:2:2, a
// 12- or 16-bit mono camera) as RGB, through OpenCV; false for any other encoding.
bool convertedByOpenCv(const sensor_msgs::Image& msg, const std::string& what, ColorImage* image) {
  namespace enc = sensor_msgs::image_encodings;
  // OpenCV names a mosaic by the second row's first two pixels: ROS's rggb is OpenCV's BG (cv_bridge's table).
  static const std::pair<std::string, int> kCodes[] = {
      {enc::BAYER_RGGB8, cv::COLOR_BayerBG2RGB},    {enc::BAYER_BGGR8, cv::COLOR_BayerRG2RGB},
      {enc::BAYER_GBRG8, cv::COLOR_BayerGR2RGB},    {enc::BAYER_GRBG8, cv::COLOR_BayerGB2RGB},
      {enc::YUV422, cv::COLOR_YUV2RGB_UYVY},        {"yuv422_yuy2", cv::COLOR_YUV2RGB_YUY2},
      {enc::MONO16, -1}};
  const auto code = std::find_if(std::begin(kCodes), std::end(kCodes), [&](const auto& c) { return msg.encoding == c.first; });
  if (code == std::end(kCodes)) return false;
  const bool mono16 = code->second < 0, packed = msg.encoding == enc::YUV422 || msg.encoding == "yuv422_yuy2";
  checkLayout(msg, mono16 || packed ? 2 : 1, what);
  if (packed && msg.width % 2 != 0) throw InputError(what + ": a " + msg.encoding + " image's width " + std::to_string(msg.width) + " is odd");
  if (mono16 && msg.is_bigendian) throw InputError(what + ": big-endian mono16 images are not supported");
  if (mono16 && msg.step % 2 != 0) throw InputError(what + ": a mono16 image's step " + std::to_string(msg.step) + " is odd");
  // The message's rows as they are (step may pad them); OpenCV only reads them.
  const cv::Mat raw(static_cast<int>(msg.height), static_cast<int>(msg.width), mono16 ? CV_16UC1 : packed ? CV_8UC2 : CV_8UC1,
                    const_cast<std::uint8_t*>(msg.data.data()), msg.step);
  cv::Mat rgb;
  try {
    if (mono16) {
      // Scaled by the image's own brightest pixel: a 12-bit camera fills only the low 4096 of 65536 levels.
      double brightest = 0.0;
      cv::minMaxLoc(raw, nullptr, &brightest);
      cv::Mat grey;
      raw.convertTo(grey, CV_8UC1, 255.0 / std::max(brightest, 1.0));
      cv::cvtColor(grey, rgb, cv::COLOR_GRAY2RGB);
    } else {
      cv::cvtColor(raw, rgb, code->second);
    }
  } catch (const cv::Exception& e) {
    throw InputError(what + ": its " + msg.encoding + " image could not be converted (" + e.err + ")");
  }
  *image = ColorImage(rgb.cols, rgb.rows);
  for (int y = 0; y < rgb.rows; ++y) {
    const cv::Vec3b* row = rgb.ptr<cv::Vec3b>(y);
    for (int x = 0; x < rgb.cols; ++x) (*image)(x, y) = Rgb8{row[x][0], row[x][1], row[x][2]};
  }
  return true;
}
}  // namespace

ColorImage fromColorImage(const sensor_msgs::Image& msg, const std::string& what) {
  namespace enc = sensor_msgs::image_encodings;
  int channels = 0, red = 0, blue = 0;
  if (msg.encoding == enc::RGB8) {
    channels = 3, red = 0, blue = 2;
  } else if (msg.encoding == enc::BGR8) {
    channels = 3, red = 2, blue = 0;
  } else if (msg.encoding == enc::RGBA8) {
    channels = 4, red = 0, blue = 2;
  } else if (msg.encoding == enc::BGRA8) {
    channels = 4, red = 2, blue = 0;
  } else if (msg.encoding == enc::MONO8) {
    channels = 1;
  } else {
    ColorImage converted;
    if (convertedByOpenCv(msg, what, &converted)) return converted;
    throw InputError(what + ": encoding '" + msg.encoding +
                     "' is not a colour image (rgb8, bgr8, rgba8, bgra8, mono8, mono16, bayer_rggb8, bayer_bggr8, bayer_gbrg8, "
                     "bayer_grbg8, yuv422, yuv422_yuy2)");
  }
  checkLayout(msg, channels, what);
  ColorImage image(msg.width, msg.height);
  for (int y = 0; y < image.height(); ++y) {
    const std::uint8_t* row = msg.data.data() + static_cast<std::size_t>(y) * msg.step;
    for (int x = 0; x < image.width(); ++x) {
      const std::uint8_t* p = row + static_cast<std::size_t>(x) * channels;
      image(x, y) = channels == 1 ? Rgb8{p[0], p[0], p[0]} : Rgb8{p[red], p[1], p[blue]};
    }
  }
  return image;
}

namespace {
// The width and height a PNG's IHDR or a JPEG's start-of-frame declares, read before decoding, so that a
// crafted header cannot make the decoder allocate gigabytes; {0, 0} for neither.
std::pair<std::uint32_t, std::uint32_t> declaredImageSize(const std::vector<std::uint8_t>& data) {
  const auto big_endian = [&](std::size_t at, int bytes) {
    std::uint32_t value = 0;
    for (int i = 0; i < bytes; ++i) value = value << 8 | data[at + i];
    return value;
  };
  static const std::uint8_t kPng[] = {0x89, 'P', 'N', 'G', 0x0d, 0x0a, 0x1a, 0x0a};
  if (data.size() >= 24 && std::equal(std::begin(kPng), std::end(kPng), data.begin())) return {big_endian(16, 4), big_endian(20, 4)};
  if (data.size() < 4 || data[0] != 0xff || data[1] != 0xd8) return {0, 0};
  // JPEG: markers from byte 2, each 0xff, a code and (but for standalone ones) a 2-byte length.
  for (std::size_t at = 2; at + 9 <= data.size();) {
    if (data[at] != 0xff) return {0, 0};
    const std::uint8_t code = data[at + 1];
    if (code == 0xff) {  // fill byte
      ++at;
      continue;
    }
    if (code >= 0xc0 && code <= 0xcf && code != 0xc4 && code != 0xc8 && code != 0xcc) return {big_endian(at + 7, 2), big_endian(at + 5, 2)};
    if (code == 0xd8 || code == 0x01 || (code >= 0xd0 && code <= 0xd7)) {
      at += 2;
      continue;
    }
    at += 2 + big_endian(at + 2, 2);
  }
  return {0, 0};
}
}  // namespace

sensor_msgs::CompressedImage toCompressedJpeg(const ColorImage& image, const std::string& frame_id, const ros::Time& stamp) {
  cv::Mat grey(image.height(), image.width(), CV_8UC1);
  for (int y = 0; y < image.height(); ++y)
    for (int x = 0; x < image.width(); ++x) grey.at<std::uint8_t>(y, x) = luma8(image(x, y));
  sensor_msgs::CompressedImage msg;
  msg.header.frame_id = frame_id;
  msg.header.stamp = stamp;
  msg.format = "mono8; jpeg compressed ";
  cv::imencode(".jpg", grey, msg.data, {cv::IMWRITE_JPEG_QUALITY, 95});
  return msg;
}

ColorImage fromCompressedColorImage(const sensor_msgs::CompressedImage& msg, const std::string& what) {
  if (msg.data.empty()) throw InputError(what + ": the compressed image is empty");
  // No camera gives more than 64 megapixels; a header that says so is not believed.
  constexpr std::uint64_t kMostPixels = 64ull << 20;
  const auto [width, height] = declaredImageSize(msg.data);
  if (width == 0 || height == 0 || static_cast<std::uint64_t>(width) * height > kMostPixels) {
    throw InputError(what + ": the compressed image (format '" + msg.format + "') is not a JPEG or PNG of at most 64 megapixels (its header says " +
                     std::to_string(width) + "x" + std::to_string(height) + ")");
  }
  cv::Mat decoded;
  try {
    decoded = cv::imdecode(cv::Mat(1, static_cast<int>(msg.data.size()), CV_8UC1, const_cast<std::uint8_t*>(msg.data.data())), cv::IMREAD_COLOR);
  } catch (const cv::Exception&) {
    decoded.release();
  }
  if (decoded.empty() || decoded.type() != CV_8UC3) {
    throw InputError(what + ": the compressed image (format '" + msg.format + "') could not be decoded as JPEG or PNG");
  }
  ColorImage image(decoded.cols, decoded.rows);
  for (int y = 0; y < image.height(); ++y) {
    const cv::Vec3b* row = decoded.ptr<cv::Vec3b>(y);
    for (int x = 0; x < image.width(); ++x) image(x, y) = Rgb8{row[x][2], row[x][1], row[x][0]};  // OpenCV decodes to BGR
  }
  return image;
}

bool isCompressedImageTopic(const std::string& topic) {
  const std::string suffix = "/compressed";
  return topic.size() > suffix.size() && topic.compare(topic.size() - suffix.size(), suffix.size(), suffix) == 0;
}

DepthImage fromDepthImage(const sensor_msgs::Image& msg, const std::string& what) {
  namespace enc = sensor_msgs::image_encodings;
  const bool millimetres = msg.encoding == enc::TYPE_16UC1 || msg.encoding == enc::MONO16;
  if (!millimetres && msg.encoding != enc::TYPE_32FC1) {
    throw InputError(what + ": encoding '" + msg.encoding + "' is not a depth image (16UC1 millimetres or 32FC1 metres)");
  }
  checkLayout(msg, millimetres ? 2 : 4, what);
  if (msg.is_bigendian) throw InputError(what + ": big-endian depth is not supported");
  DepthImage depth(msg.width, msg.height);
  for (int y = 0; y < depth.height(); ++y) {
    const std::uint8_t* row = msg.data.data() + static_cast<std::size_t>(y) * msg.step;
    for (int x = 0; x < depth.width(); ++x) {
      float metres;
      if (millimetres) {
        std::uint16_t raw;
        std::memcpy(&raw, row + 2 * x, 2);
        metres = raw * 0.001f;
      } else {
        std::memcpy(&metres, row + 4 * x, 4);
      }
      depth(x, y) = std::isfinite(metres) && metres > 0.0f ? metres : 0.0f;
    }
  }
  return depth;
}

LensDistortion lensDistortionFromCameraInfo(const sensor_msgs::CameraInfo& msg, const std::string& what) {
  return LensDistortion::fromCameraInfo(msg.distortion_model, msg.D, what);
}

LensDistortion odometryLensFromCameraInfo(const sensor_msgs::CameraInfo& msg, const std::string& what, std::string* problem) {
  problem->clear();
  try {
    return lensDistortionFromCameraInfo(msg, what);
  } catch (const InputError& e) {
    *problem = std::string(e.what()) + ": tracking without undoing the lens";
    return LensDistortion();
  }
}

PinholeCamera fromCameraInfo(const sensor_msgs::CameraInfo& msg, const std::string& what) {
  if (msg.K[0] == 0.0 || msg.K[4] == 0.0) {
    throw InputError(what + ": K has zero focal lengths: the camera is not calibrated");
  }
  if (msg.binning_x > 1 || msg.binning_y > 1 || msg.roi.width != 0 || msg.roi.height != 0) {
    throw InputError(what + ": binning or a region of interest is set; publish the full-resolution calibration");
  }
  PinholeCamera camera;
  camera.width = static_cast<int>(msg.width);
  camera.height = static_cast<int>(msg.height);
  camera.fx = msg.K[0];
  camera.fy = msg.K[4];
  camera.cx = msg.K[2];
  camera.cy = msg.K[5];
  camera.depth_scale = 1000.0;
  camera.validate(what);
  return camera;
}

namespace {
// An integer field's value at `p` (PointField datatypes INT8 ... UINT32).
int integerAt(const std::uint8_t* p, std::uint8_t datatype) {
  switch (datatype) {
    case sensor_msgs::PointField::INT8: return *reinterpret_cast<const std::int8_t*>(p);
    case sensor_msgs::PointField::UINT8: return *p;
    case sensor_msgs::PointField::INT16: { std::int16_t v; std::memcpy(&v, p, 2); return v; }
    case sensor_msgs::PointField::UINT16: { std::uint16_t v; std::memcpy(&v, p, 2); return v; }
    case sensor_msgs::PointField::INT32: { std::int32_t v; std::memcpy(&v, p, 4); return v; }
    default: { std::uint32_t v; std::memcpy(&v, p, 4); return static_cast<int>(std::min<std::uint32_t>(v, 1u << 30)); }
  }
}
}  // namespace

std::vector<Eigen::Vector3d> fromPointCloud2(const sensor_msgs::PointCloud2& msg, const std::string& what, std::vector<int>* rings) {
  // Offsets as given (any 32-bit value); -1 where the field is missing.
  std::int64_t offsets[3] = {-1, -1, -1};
  std::uint8_t types[3] = {0, 0, 0};
  const char* names[] = {"x", "y", "z"};
  int ring_offset = -1;
  std::uint8_t ring_type = 0;
  for (const sensor_msgs::PointField& field : msg.fields) {
    for (int axis = 0; axis < 3; ++axis) {
      if (field.name == names[axis]) offsets[axis] = field.offset, types[axis] = field.datatype;
    }
    const std::size_t ring_size = field.datatype <= sensor_msgs::PointField::UINT8 ? 1 : field.datatype <= sensor_msgs::PointField::UINT16 ? 2 : 4;
    if (field.name == "ring" && field.datatype >= sensor_msgs::PointField::INT8 && field.datatype <= sensor_msgs::PointField::UINT32 &&
        field.offset + ring_size <= msg.point_step) {
      ring_offset = static_cast<int>(field.offset), ring_type = field.datatype;
    }
  }
  if (rings) rings->clear();
  for (int axis = 0; axis < 3; ++axis) {
    if (offsets[axis] < 0) throw InputError(what + ": the cloud has no '" + names[axis] + "' field");
    if (types[axis] != sensor_msgs::PointField::FLOAT32 && types[axis] != sensor_msgs::PointField::FLOAT64) {
      throw InputError(what + ": field '" + names[axis] + "' is not float32 or float64");
    }
    const std::size_t size = types[axis] == sensor_msgs::PointField::FLOAT32 ? 4 : 8;
    if (offsets[axis] + size > msg.point_step) throw InputError(what + ": field '" + names[axis] + "' lies outside point_step");
  }
  if (msg.is_bigendian) throw InputError(what + ": big-endian clouds are not supported");
  const std::size_t count = static_cast<std::size_t>(msg.width) * msg.height;
  // 64-bit products: 32-bit width x point_step wraps for a corrupt header and would pass the check.
  if (msg.height > 0 && (msg.row_step < static_cast<std::size_t>(msg.width) * msg.point_step ||
                         msg.data.size() < static_cast<std::size_t>(msg.row_step) * msg.height)) {
    throw InputError(what + ": data holds " + std::to_string(msg.data.size()) + " bytes, too few for " + std::to_string(count) +
                     " points");
  }
  // Found by fuzzing: width 0 and a height of billions passed every check and spun through empty rows for seconds.
  if (count == 0) return {};
  std::vector<Eigen::Vector3d> points;
  points.reserve(count);
  for (std::uint32_t row = 0; row < msg.height; ++row) {
    for (std::uint32_t column = 0; column < msg.width; ++column) {
      const std::uint8_t* p =
          msg.data.data() + static_cast<std::size_t>(row) * msg.row_step + static_cast<std::size_t>(column) * msg.point_step;
      Eigen::Vector3d point;
      for (int axis = 0; axis < 3; ++axis) {
        if (types[axis] == sensor_msgs::PointField::FLOAT32) {
          float value;
          std::memcpy(&value, p + offsets[axis], 4);
          point[axis] = value;
        } else {
          std::memcpy(&point[axis], p + offsets[axis], 8);
        }
      }
      // A no-return: NaN (velodyne_pointcloud's organised clouds) or the origin itself (an Ouster
      // driver's organised 1024 x 64 cloud holds a few thousand a scan; kept, they all fell into one
      // cluster whose neighbour searches took minutes, and into every ring's elevation).
      if (!point.allFinite() || (point.x() == 0.0 && point.y() == 0.0 && point.z() == 0.0)) continue;
      points.push_back(point);
      if (rings && ring_offset >= 0) rings->push_back(integerAt(p + ring_offset, ring_type));
    }
  }
  return points;
}

std::vector<Eigen::Vector3d> fromLaserScan(const sensor_msgs::LaserScan& msg, const std::string& what) {
  if (!(msg.angle_increment != 0.0f) || !std::isfinite(msg.angle_increment) || !std::isfinite(msg.angle_min)) {
    throw InputError(what + ": angle_min must be finite and angle_increment finite and non-zero");
  }
  // Beyond a few turns the angles are corrupt (and far enough out, not finite).
  const double last_angle = msg.angle_min + static_cast<double>(msg.ranges.size()) * msg.angle_increment;
  if (std::abs(msg.angle_min) > 8.0 * M_PI || std::abs(last_angle) > 8.0 * M_PI) {
    throw InputError(what + ": angle_min " + std::to_string(msg.angle_min) + " and " + std::to_string(msg.ranges.size()) +
                     " beams of angle_increment " + std::to_string(msg.angle_increment) + " span more than four turns");
  }
  std::vector<Eigen::Vector3d> points;
  for (std::size_t i = 0; i < msg.ranges.size(); ++i) {
    const float r = msg.ranges[i];
    if (!std::isfinite(r) || r < msg.range_min || r > msg.range_max) continue;
    const double angle = msg.angle_min + i * static_cast<double>(msg.angle_increment);
    points.emplace_back(r * std::cos(angle), r * std::sin(angle), 0.0);
  }
  return points;
}

sensor_msgs::LaserScan toLaserScan(const std::vector<float>& ranges, double angle_min, double angle_increment,
                                   double range_max, const std::string& frame_id, const ros::Time& stamp) {
  sensor_msgs::LaserScan msg;
  msg.header.stamp = stamp;
  msg.header.frame_id = frame_id;
  msg.angle_min = static_cast<float>(angle_min);
  msg.angle_increment = static_cast<float>(angle_increment);
  msg.angle_max = static_cast<float>(angle_min + angle_increment * (ranges.empty() ? 0 : ranges.size() - 1));
  msg.range_min = 0.05f;
  msg.range_max = static_cast<float>(range_max);
  msg.ranges = ranges;
  return msg;
}

RgbdFrame toRgbdFrame(const sensor_msgs::Image& color, const sensor_msgs::Image& depth, const std::string& color_what,
                      const std::string& depth_what) {
  RgbdFrame frame;
  frame.stamp = color.header.stamp.toSec();
  frame.color = fromColorImage(color, color_what);
  frame.depth = fromDepthImage(depth, depth_what);
  if (!frame.color.sameSize(frame.depth)) {
    std::ostringstream message;
    message << depth_what << ": depth is " << frame.depth.width() << "x" << frame.depth.height() << " but " << color_what
            << " is " << frame.color.width() << "x" << frame.color.height()
            << " (depth must be registered to the colour image)";
    throw InputError(message.str());
  }
  return frame;
}

sensor_msgs::Imu toAccelerometerImu(const AccelerometerSample& sample, const std::string& frame_id) {
  sensor_msgs::Imu msg;
  msg.header.stamp = ros::Time(sample.stamp);
  msg.header.frame_id = frame_id;
  msg.orientation_covariance[0] = -1.0;
  msg.angular_velocity_covariance[0] = -1.0;
  msg.linear_acceleration.x = sample.specific_force.x();
  msg.linear_acceleration.y = sample.specific_force.y();
  msg.linear_acceleration.z = sample.specific_force.z();
  return msg;
}

sensor_msgs::Imu toImuMessage(const ImuSample& sample, const std::string& frame_id) {
  sensor_msgs::Imu msg;
  msg.header.stamp = ros::Time(sample.stamp);
  msg.header.frame_id = frame_id;
  msg.orientation_covariance[0] = -1.0;
  msg.angular_velocity.x = sample.angular_velocity.x();
  msg.angular_velocity.y = sample.angular_velocity.y();
  msg.angular_velocity.z = sample.angular_velocity.z();
  msg.linear_acceleration.x = sample.linear_acceleration.x();
  msg.linear_acceleration.y = sample.linear_acceleration.y();
  msg.linear_acceleration.z = sample.linear_acceleration.z();
  return msg;
}

AccelerometerSample fromImuAcceleration(const sensor_msgs::Imu& msg, const std::string& what) {
  AccelerometerSample sample;
  sample.stamp = msg.header.stamp.toSec();
  sample.specific_force = Eigen::Vector3d(msg.linear_acceleration.x, msg.linear_acceleration.y, msg.linear_acceleration.z);
  if (!sample.specific_force.allFinite()) {
    std::ostringstream message;
    message << what << ": linear_acceleration (" << msg.linear_acceleration.x << ", " << msg.linear_acceleration.y << ", "
            << msg.linear_acceleration.z << ") is not finite";
    throw InputError(message.str());
  }
  return sample;
}

ImuSample fromImuMessage(const sensor_msgs::Imu& msg, const std::string& what) {
  ImuSample sample;
  sample.stamp = msg.header.stamp.toSec();
  sample.angular_velocity = Eigen::Vector3d(msg.angular_velocity.x, msg.angular_velocity.y, msg.angular_velocity.z);
  sample.linear_acceleration = Eigen::Vector3d(msg.linear_acceleration.x, msg.linear_acceleration.y, msg.linear_acceleration.z);
  if (!sample.angular_velocity.allFinite() || !sample.linear_acceleration.allFinite()) {
    std::ostringstream message;
    message << what << ": angular_velocity (" << msg.angular_velocity.x << ", " << msg.angular_velocity.y << ", " << msg.angular_velocity.z
            << ") or linear_acceleration is not finite";
    throw InputError(message.str());
  }
  return sample;
}

}  // namespace vocal
