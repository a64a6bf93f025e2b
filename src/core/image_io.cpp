#include "vocal/core/image_io.h"

#include <cmath>
#include <sstream>

#include <opencv2/imgcodecs.hpp>

#include "vocal/core/errors.h"

namespace vocal {

namespace {
cv::Mat readPng(const std::string& path) {
  cv::Mat mat = cv::imread(path, cv::IMREAD_UNCHANGED);
  if (mat.empty()) {
    throw InputError(path + ": cannot read image (missing file or not an image)");
  }
  return mat;
}

void writePng(const std::string& path, const cv::Mat& mat) {
  bool ok = false;
  try {
    ok = cv::imwrite(path, mat);
  } catch (const cv::Exception& e) {
    throw InputError(path + ": cannot write image (" + e.what() + ")");
  }
  if (!ok) {
    throw InputError(path + ": cannot write image");
  }
}

std::string describe(const cv::Mat& mat) {
  std::ostringstream s;
  s << mat.channels() << " channel(s) of " << (mat.depth() == CV_8U ? "8-bit" : mat.depth() == CV_16U ? "16-bit" : "other")
    << " data";
  return s.str();
}
}  // namespace

ColorImage readColorPng(const std::string& path) {
  const cv::Mat mat = readPng(path);
  if (mat.depth() != CV_8U || (mat.channels() != 1 && mat.channels() != 3 && mat.channels() != 4)) {
    throw InputError(path + ": expected an 8-bit grey, RGB or RGBA image, found " + describe(mat));
  }
  ColorImage image(mat.cols, mat.rows);
  for (int y = 0; y < mat.rows; ++y) {
    const std::uint8_t* row = mat.ptr<std::uint8_t>(y);
    for (int x = 0; x < mat.cols; ++x) {
      const std::uint8_t* px = row + x * mat.channels();
      // OpenCV stores BGR(A).
      image(x, y) = mat.channels() == 1 ? Rgb8{px[0], px[0], px[0]} : Rgb8{px[2], px[1], px[0]};
    }
  }
  return image;
}

void writeColorPng(const std::string& path, const ColorImage& image) {
  cv::Mat mat(image.height(), image.width(), CV_8UC3);
  for (int y = 0; y < image.height(); ++y) {
    for (int x = 0; x < image.width(); ++x) {
      const Rgb8& p = image(x, y);
      mat.at<cv::Vec3b>(y, x) = cv::Vec3b(p.b, p.g, p.r);
    }
  }
  writePng(path, mat);
}

DepthImage readDepthPng(const std::string& path, double depth_scale) {
  const cv::Mat mat = readPng(path);
  if (mat.depth() != CV_16U || mat.channels() != 1) {
    throw InputError(path + ": expected a 16-bit single-channel depth image, found " + describe(mat));
  }
  DepthImage depth(mat.cols, mat.rows);
  const double metres_per_unit = 1.0 / depth_scale;
  for (int y = 0; y < mat.rows; ++y) {
    const std::uint16_t* row = mat.ptr<std::uint16_t>(y);
    for (int x = 0; x < mat.cols; ++x) {
      depth(x, y) = static_cast<float>(row[x] * metres_per_unit);
    }
  }
  return depth;
}

void writeDepthPng(const std::string& path, const DepthImage& depth, double depth_scale) {
  cv::Mat mat(depth.height(), depth.width(), CV_16UC1);
  for (int y = 0; y < depth.height(); ++y) {
    for (int x = 0; x < depth.width(); ++x) {
      const float z = depth(x, y);
      const double units = isValidDepth(z) ? std::round(z * depth_scale) : 0.0;
      mat.at<std::uint16_t>(y, x) = units <= 65535.0 ? static_cast<std::uint16_t>(units) : 0;
    }
  }
  writePng(path, mat);
}

}  // namespace vocal
