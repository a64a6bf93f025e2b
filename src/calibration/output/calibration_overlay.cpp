#include "vocal/calibration/output/calibration_overlay.h"

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

namespace vocal {

OverlayAgreement overlayAgreement(const std::vector<Eigen::Vector3d>& points, const Eigen::Isometry3d& camera_from_board,
                                  double width, double height, double margin) {
  OverlayAgreement agreement;
  const Eigen::Isometry3d board_from_camera = camera_from_board.inverse();
  double squared = 0.0;
  int on_board = 0;
  for (const Eigen::Vector3d& p : points) {
    const Eigen::Vector3d q = board_from_camera * p;
    on_board += std::abs(q.x()) <= 0.5 * width + margin && std::abs(q.y()) <= 0.5 * height + margin;
    squared += q.z() * q.z();
  }
  agreement.points = static_cast<int>(points.size());
  if (!points.empty()) {
    agreement.on_board = static_cast<double>(on_board) / points.size();
    agreement.plane_rms = std::sqrt(squared / points.size());
  }
  return agreement;
}

namespace {
bool pixelOf(const PinholeCamera& camera, const LensDistortion& lens, const Eigen::Vector3d& p, cv::Point* pixel) {
  if (p.z() <= 0.05) return false;
  const Eigen::Vector2d uv = projectThroughLens(camera, lens, p);
  if (!camera.contains(uv.x(), uv.y())) return false;
  *pixel = cv::Point(static_cast<int>(std::lround(uv.x())), static_cast<int>(std::lround(uv.y())));
  return true;
}
}  // namespace

ColorImage drawCalibrationOverlay(const ColorImage& image, const PinholeCamera& camera, const LensDistortion& lens,
                                  const OverlayBoard& board, const std::vector<OverlayLayer>& layers,
                                  const std::string& title) {
  ColorImage out = image;
  // The pixels in place: RGB in memory, so OpenCV's first channel is red here.
  cv::Mat canvas(out.height(), out.width(), CV_8UC3, out.data());
  const auto colour = [](const Rgb8& c) { return cv::Scalar(c.r, c.g, c.b); };
  const Rgb8 green{40, 220, 40};
  if (board.width > 0.0) {
    // The outline sampled along each edge: a fisheye bends straight edges.
    const double hw = 0.5 * board.width, hh = 0.5 * board.height;
    const Eigen::Vector2d ends[5] = {{-hw, -hh}, {hw, -hh}, {hw, hh}, {-hw, hh}, {-hw, -hh}};
    for (int e = 0; e < 4; ++e) {
      cv::Point previous;
      bool have_previous = false;
      for (int k = 0; k <= 32; ++k) {
        const Eigen::Vector2d xy = ends[e] + (ends[e + 1] - ends[e]) * (k / 32.0);
        cv::Point pixel;
        const bool seen = pixelOf(camera, lens, board.camera_from_board * Eigen::Vector3d(xy.x(), xy.y(), 0.0), &pixel);
        if (seen && have_previous) cv::line(canvas, previous, pixel, colour(green), 2, cv::LINE_AA);
        previous = pixel;
        have_previous = seen;
      }
    }
    for (const Eigen::Vector2d& c : board.corners) {
      const cv::Point p(static_cast<int>(std::lround(c.x())), static_cast<int>(std::lround(c.y())));
      cv::drawMarker(canvas, p, colour(green), cv::MARKER_CROSS, 7, 1);
    }
  }
  for (const OverlayLayer& layer : layers) {
    for (const Eigen::Vector3d& p : layer.points) {
      cv::Point pixel;
      if (pixelOf(camera, lens, p, &pixel)) cv::circle(canvas, pixel, 2, colour(layer.colour), cv::FILLED);
    }
  }
  // Legend: the title, then each layer's name in its colour, on a dark band so it reads on any image.
  const int line = 18;
  int widest = cv::getTextSize(title, cv::FONT_HERSHEY_SIMPLEX, 0.45, 1, nullptr).width;
  for (const OverlayLayer& layer : layers)
    widest = std::max(widest, cv::getTextSize(layer.label, cv::FONT_HERSHEY_SIMPLEX, 0.45, 1, nullptr).width);
  cv::rectangle(canvas, cv::Rect(0, 0, std::min(out.width(), widest + 10), line * static_cast<int>(layers.size() + 1) + 6),
                cv::Scalar(0, 0, 0), cv::FILLED);
  cv::putText(canvas, title, cv::Point(5, line), cv::FONT_HERSHEY_SIMPLEX, 0.45, colour(green), 1, cv::LINE_AA);
  for (std::size_t i = 0; i < layers.size(); ++i) {
    cv::putText(canvas, layers[i].label, cv::Point(5, line * static_cast<int>(i + 2)), cv::FONT_HERSHEY_SIMPLEX, 0.45,
                colour(layers[i].colour), 1, cv::LINE_AA);
  }
  return out;
}

ColorImage labelledThumbnail(const ColorImage& image, int width, const std::string& label) {
  constexpr int kStrip = 18;  // pixels: one line of text
  const int height = std::max(1, static_cast<int>(std::lround(static_cast<double>(image.height()) * width / image.width())));
  ColorImage out(width, height + kStrip);
  const cv::Mat source(image.height(), image.width(), CV_8UC3, const_cast<Rgb8*>(image.data()));
  cv::Mat canvas(out.height(), out.width(), CV_8UC3, out.data());
  cv::resize(source, canvas(cv::Rect(0, 0, width, height)), cv::Size(width, height), 0.0, 0.0, cv::INTER_AREA);
  cv::putText(canvas, label, cv::Point(3, height + kStrip - 5), cv::FONT_HERSHEY_SIMPLEX, 0.4, cv::Scalar(255, 255, 255), 1,
              cv::LINE_AA);
  return out;
}

ColorImage contactSheet(const std::vector<ColorImage>& thumbnails, int columns) {
  if (thumbnails.empty() || columns < 1) return ColorImage();
  int cell_width = 0, cell_height = 0;
  for (const ColorImage& t : thumbnails) {  // an empty one has size 0 x 0
    cell_width = std::max(cell_width, t.width());
    cell_height = std::max(cell_height, t.height());
  }
  columns = std::min<int>(columns, thumbnails.size());
  const int rows = (static_cast<int>(thumbnails.size()) + columns - 1) / columns;
  ColorImage sheet(columns * cell_width, rows * cell_height, Rgb8{40, 40, 40});
  for (std::size_t i = 0; i < thumbnails.size(); ++i) {
    const int x0 = static_cast<int>(i % columns) * cell_width, y0 = static_cast<int>(i / columns) * cell_height;
    for (int y = 0; y < thumbnails[i].height(); ++y)
      for (int x = 0; x < thumbnails[i].width(); ++x) sheet(x0 + x, y0 + y) = thumbnails[i](x, y);
  }
  return sheet;
}

}  // namespace vocal
