#include "vocal/tools/trajectory_plot.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "vocal/core/errors.h"

namespace vocal {

namespace {
const cv::Scalar kBlack(0, 0, 0), kGrey(215, 215, 215), kTruth(40, 40, 40), kEstimate(200, 90, 20),
    kError(60, 60, 220), kLink(170, 170, 255);

// Maps data coordinates into a pixel rectangle and draws a labelled grid.
struct PlotAxes {
  cv::Rect area;
  double x0, x1, y0, y1;

  cv::Point map(double x, double y) const {
    return {area.x + static_cast<int>(std::lround((x - x0) / (x1 - x0) * area.width)),
            area.y + area.height - static_cast<int>(std::lround((y - y0) / (y1 - y0) * area.height))};
  }

  static double niceStep(double span) {
    const double raw = span / 6.0;
    const double magnitude = std::pow(10.0, std::floor(std::log10(raw)));
    for (double m : {1.0, 2.0, 5.0, 10.0}) {
      if (m * magnitude >= raw) return m * magnitude;
    }
    return 10.0 * magnitude;
  }

  void draw(cv::Mat* image, const std::string& x_label, const std::string& y_label, const std::string& title) const {
    char text[64];
    const double xs = niceStep(x1 - x0), ys = niceStep(y1 - y0);
    for (double x = std::ceil(x0 / xs) * xs; x <= x1; x += xs) {
      cv::line(*image, map(x, y0), map(x, y1), kGrey, 1);
      std::snprintf(text, sizeof(text), "%g", std::abs(x) < 1e-12 ? 0.0 : x);
      cv::putText(*image, text, map(x, y0) + cv::Point(-12, 18), cv::FONT_HERSHEY_SIMPLEX, 0.4, kBlack, 1, cv::LINE_AA);
    }
    for (double y = std::ceil(y0 / ys) * ys; y <= y1; y += ys) {
      cv::line(*image, map(x0, y), map(x1, y), kGrey, 1);
      std::snprintf(text, sizeof(text), "%g", std::abs(y) < 1e-12 ? 0.0 : y);
      cv::putText(*image, text, map(x0, y) + cv::Point(-48, 4), cv::FONT_HERSHEY_SIMPLEX, 0.4, kBlack, 1, cv::LINE_AA);
    }
    cv::rectangle(*image, area, kBlack, 1);
    cv::putText(*image, x_label, cv::Point(area.x + area.width / 2 - 30, area.y + area.height + 38),
                cv::FONT_HERSHEY_SIMPLEX, 0.5, kBlack, 1, cv::LINE_AA);
    cv::putText(*image, y_label, cv::Point(area.x - 50, area.y - 10), cv::FONT_HERSHEY_SIMPLEX, 0.5, kBlack, 1,
                cv::LINE_AA);
    cv::putText(*image, title, cv::Point(area.x, area.y - 32), cv::FONT_HERSHEY_SIMPLEX, 0.55, kBlack, 1, cv::LINE_AA);
  }
};

void legend(cv::Mat* image, cv::Point at, const cv::Scalar& colour, const std::string& label) {
  cv::line(*image, at, at + cv::Point(30, 0), colour, 2, cv::LINE_AA);
  cv::putText(*image, label, at + cv::Point(38, 5), cv::FONT_HERSHEY_SIMPLEX, 0.45, kBlack, 1, cv::LINE_AA);
}
}  // namespace

void writeTrajectoryPlot(const std::string& path, const AteResult& ate, const std::string& title) {
  cv::Mat image(710, 1400, CV_8UC3, cv::Scalar(255, 255, 255));

  // Top view with equal scale on both axes.
  double min_x = 1e300, max_x = -1e300, min_y = 1e300, max_y = -1e300;
  for (const auto* list : {&ate.ground_truth, &ate.aligned_estimate}) {
    for (const Eigen::Vector3d& p : *list) {
      min_x = std::min(min_x, p.x()), max_x = std::max(max_x, p.x());
      min_y = std::min(min_y, p.y()), max_y = std::max(max_y, p.y());
    }
  }
  const double half = 0.55 * std::max({max_x - min_x, max_y - min_y, 0.01});
  const double cx = 0.5 * (min_x + max_x), cy = 0.5 * (min_y + max_y);
  const PlotAxes top{cv::Rect(90, 100, 520, 520), cx - half, cx + half, cy - half, cy + half};
  top.draw(&image, "x [m]", "y [m]", "Top view (estimate aligned to ground truth)");
  for (std::size_t i = 0; i < ate.ground_truth.size(); ++i) {
    const auto& g = ate.ground_truth[i];
    const auto& e = ate.aligned_estimate[i];
    cv::line(image, top.map(g.x(), g.y()), top.map(e.x(), e.y()), kLink, 1, cv::LINE_AA);
  }
  for (std::size_t i = 1; i < ate.ground_truth.size(); ++i) {
    const auto& g0 = ate.ground_truth[i - 1];
    const auto& g1 = ate.ground_truth[i];
    const auto& e0 = ate.aligned_estimate[i - 1];
    const auto& e1 = ate.aligned_estimate[i];
    cv::line(image, top.map(g0.x(), g0.y()), top.map(g1.x(), g1.y()), kTruth, 2, cv::LINE_AA);
    cv::line(image, top.map(e0.x(), e0.y()), top.map(e1.x(), e1.y()), kEstimate, 2, cv::LINE_AA);
  }
  legend(&image, cv::Point(100, 690), kTruth, "ground truth");
  legend(&image, cv::Point(260, 690), kEstimate, "estimate");
  legend(&image, cv::Point(400, 690), kLink, "difference");

  // Error over time.
  const double t0 = ate.stamps.front();
  const double t1 = std::max(ate.stamps.back() - t0, 1e-3);
  const double e1 = std::max(ate.max * 1.1, 1e-6);
  const PlotAxes errors{cv::Rect(780, 100, 580, 520), 0.0, t1, 0.0, e1};
  char heading[160];
  std::snprintf(heading, sizeof(heading), "Position error (ATE): RMSE %.4f, median %.4f, max %.4f m", ate.rmse,
                ate.median, ate.max);
  errors.draw(&image, "time [s]", "error [m]", heading);
  for (std::size_t i = 1; i < ate.errors.size(); ++i) {
    cv::line(image, errors.map(ate.stamps[i - 1] - t0, ate.errors[i - 1]), errors.map(ate.stamps[i] - t0, ate.errors[i]),
             kError, 2, cv::LINE_AA);
  }
  cv::putText(image, title, cv::Point(90, 30), cv::FONT_HERSHEY_SIMPLEX, 0.6, kBlack, 1, cv::LINE_AA);

  bool ok = false;
  try {
    ok = cv::imwrite(path, image);
  } catch (const cv::Exception& e) {
    throw InputError(path + ": cannot write plot (" + e.what() + ")");
  }
  if (!ok) throw InputError(path + ": cannot write plot");
}

}  // namespace vocal
