#pragma once
// A minimal owning 2D image, so core headers stay free of OpenCV (slow to compile, and the
// OpenCL backend only needs a contiguous buffer it can upload).

#include <cstdint>
#include <vector>

namespace vocal {

struct Rgb8 {
  std::uint8_t r = 0;
  std::uint8_t g = 0;
  std::uint8_t b = 0;
};

inline bool operator==(const Rgb8& a, const Rgb8& b) { return a.r == b.r && a.g == b.g && a.b == b.b; }

// 8-bit luma (ITU-R BT.601 weights), as OpenCV's and ROS's mono conversions compute it.
inline std::uint8_t luma8(const Rgb8& p) { return static_cast<std::uint8_t>((299 * p.r + 587 * p.g + 114 * p.b) / 1000); }

template <typename T>
class Image {
 public:
  Image() = default;
  Image(int width, int height, const T& fill = T())
      : width_(width), height_(height), pixels_(static_cast<std::size_t>(width) * height, fill) {}

  int width() const { return width_; }
  int height() const { return height_; }
  bool empty() const { return pixels_.empty(); }
  std::size_t size() const { return pixels_.size(); }
  bool sameSize(int width, int height) const { return width_ == width && height_ == height; }
  template <typename U>
  bool sameSize(const Image<U>& other) const { return sameSize(other.width(), other.height()); }

  T& operator()(int x, int y) { return pixels_[static_cast<std::size_t>(y) * width_ + x]; }
  const T& operator()(int x, int y) const { return pixels_[static_cast<std::size_t>(y) * width_ + x]; }

  T* data() { return pixels_.data(); }
  const T* data() const { return pixels_.data(); }
  std::vector<T>& pixels() { return pixels_; }
  const std::vector<T>& pixels() const { return pixels_; }

 private:
  int width_ = 0;
  int height_ = 0;
  std::vector<T> pixels_;
};

using ColorImage = Image<Rgb8>;
// Depth in metres; 0 (or any non-finite value) marks a pixel without a measurement.
using DepthImage = Image<float>;

inline bool isValidDepth(float depth_m) { return depth_m > 0.0f && depth_m < 1e30f; }

}  // namespace vocal
