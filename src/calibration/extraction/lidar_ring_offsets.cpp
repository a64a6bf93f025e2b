#include "vocal/calibration/extraction/lidar_ring_offsets.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <string>

#include <Eigen/Cholesky>
#include <Eigen/LU>

#include "vocal/calibration/point_statistics.h"
#include "vocal/core/errors.h"

namespace vocal {

namespace {
double elevationOf(const Eigen::Vector3d& p) { return std::atan2(p.z(), p.head<2>().norm()); }

// RingOffsetEstimator::plane_offset_information_'s bins.
constexpr double kOffsetBin = 0.001;
constexpr int kOffsetBins = 2001;  // -1 m ... +1 m
double offsetOfBin(int bin) { return (bin - kOffsetBins / 2) * kOffsetBin; }
int binOfOffset(double offset) {
  return std::clamp(static_cast<int>(std::lround(offset / kOffsetBin)) + kOffsetBins / 2, 0, kOffsetBins - 1);
}
}  // namespace

std::vector<LidarRing> lidarRingsOf(const std::vector<Eigen::Vector3d>& cloud) {
  std::vector<double> elevations;
  elevations.reserve(cloud.size());
  for (const Eigen::Vector3d& p : cloud) elevations.push_back(elevationOf(p));
  std::sort(elevations.begin(), elevations.end());
  std::vector<LidarRing> rings;
  for (std::size_t i = 0; i < elevations.size();) {
    std::size_t j = i;
    double sum = 0.0;
    while (j < elevations.size() && elevations[j] - elevations[i] < 0.2 * M_PI / 180.0) sum += elevations[j++];
    rings.push_back({sum / (j - i), j - i});
    i = j;
  }
  return rings;
}

int RingOffsets::ringOf(const Eigen::Vector3d& point) const {
  const double elevation = elevationOf(point);
  const auto above = std::lower_bound(elevations.begin(), elevations.end(), elevation);
  int ring = static_cast<int>(above - elevations.begin());
  if (ring == static_cast<int>(elevations.size()) || (ring > 0 && elevation - elevations[ring - 1] < *above - elevation)) --ring;
  return std::abs(elevation - elevations[ring]) < 0.5 * spacing ? ring : -1;
}

std::string RingOffsets::range() const {
  if (offsets.size() == 0) return "none";
  char text[64];
  std::snprintf(text, sizeof(text), "%+.1f to %+.1f mm", 1000 * offsets.minCoeff(), 1000 * offsets.maxCoeff());
  return text;
}

Eigen::Vector3d RingOffsets::corrected(const Eigen::Vector3d& point) const {
  const int ring = ringOf(point);
  const double range = point.norm();
  if (ring < 0 || !(range > 0.0)) return point;
  return point * ((range - offsets[ring]) / range);
}

RingOffsetEstimator::RingOffsetEstimator(std::vector<double> elevations, RingOffsetOptions options) : options_(options) {
  if (elevations.size() < 2) {
    throw InputError("lidar ring offsets: " + std::to_string(elevations.size()) + " ring(s) of returns; a spinning lidar has 2 or more");
  }
  std::sort(elevations.begin(), elevations.end());
  std::vector<double> gaps;
  for (std::size_t r = 1; r < elevations.size(); ++r) gaps.push_back(elevations[r] - elevations[r - 1]);
  rings_.spacing = median(gaps);
  rings_.elevations = std::move(elevations);
  const Eigen::Index n = static_cast<Eigen::Index>(rings_.elevations.size());
  normal_ = Eigen::MatrixXd::Zero(n, n);
  gradient_ = Eigen::VectorXd::Zero(n);
  plane_offset_information_.assign(kOffsetBins, 0.0);
}

void RingOffsetEstimator::addPlanes(const std::vector<std::vector<Eigen::Vector3d>>& planes) {
  std::vector<PrincipalAxes> fitted;
  for (const std::vector<Eigen::Vector3d>& points : planes) fitted.push_back(principalAxesOf(points));
  for (std::size_t k = 0; k < planes.size(); ++k) {
    std::vector<Eigen::Vector3d> away;
    for (const Eigen::Vector3d& p : planes[k]) {
      bool near_another = false;
      for (std::size_t j = 0; j < planes.size() && !near_another; ++j)
        near_another = j != k && std::abs(fitted[j].axes.col(2).dot(p - fitted[j].centroid)) < options_.corner_margin;
      if (!near_another) away.push_back(p);
    }
    addPlane(away);
  }
}

void RingOffsetEstimator::addPlane(const std::vector<Eigen::Vector3d>& points) {
  if (points.size() < options_.min_plane_points) return;
  const PrincipalAxes plane = principalAxesOf(points);
  const Eigen::Vector3d normal = plane.axes.col(2);
  std::vector<double> incidence;
  incidence.reserve(points.size());
  for (const Eigen::Vector3d& p : points) incidence.push_back(std::abs(normal.dot(p.normalized())));
  if (median(std::move(incidence)) < options_.min_incidence) {
    ++grazing_planes_;
    return;
  }
  const Eigen::Index rings = normal_.rows();
  // Each return's distance e from the plane as measured against its ring's offset b (along the ray:
  // b times the ray's cosine to the normal) and a small change of the plane (tilts a1, a2 about its
  // in-plane axes, shift a3): e = b (n.u) - a1 (t1.d) - a2 (t2.d) + a3, d the return from the centroid.
  Eigen::Matrix3d plane_block = Eigen::Matrix3d::Zero();
  Eigen::MatrixXd cross = Eigen::MatrixXd::Zero(3, rings);
  Eigen::VectorXd ring_diagonal = Eigen::VectorXd::Zero(rings), ring_gradient = Eigen::VectorXd::Zero(rings);
  Eigen::Vector3d plane_gradient = Eigen::Vector3d::Zero();
  double squares = 0.0;
  std::size_t used = 0;
  for (const Eigen::Vector3d& p : points) {
    const int ring = rings_.ringOf(p);
    if (ring < 0) continue;
    const Eigen::Vector3d d = p - plane.centroid;
    const double e = normal.dot(d), along = normal.dot(p.normalized());
    const Eigen::Vector3d a(-plane.axes.col(0).dot(d), -plane.axes.col(1).dot(d), 1.0);
    plane_block += a * a.transpose();
    cross.col(ring) += a * along;
    ring_diagonal[ring] += along * along;
    plane_gradient += a * e;
    ring_gradient[ring] += along * e;
    squares += e * e;
    ++used;
  }
  if (used < options_.min_plane_points) return;
  const Eigen::Matrix3d plane_inverse = plane_block.inverse();
  // One offset for every ring, this plane's pose eliminated: its own say on a common offset.
  const Eigen::Vector3d cross_sum = cross.rowwise().sum();
  const double common_information = ring_diagonal.sum() - cross_sum.dot(plane_inverse * cross_sum);
  if (common_information > 1e-9 * ring_diagonal.sum()) {
    const double common_gradient = ring_gradient.sum() - cross_sum.dot(plane_inverse * plane_gradient);
    plane_offset_information_[binOfOffset(common_gradient / common_information)] += common_information;
  }
  normal_ += Eigen::MatrixXd(ring_diagonal.asDiagonal()) - cross.transpose() * plane_inverse * cross;
  gradient_ += ring_gradient - cross.transpose() * (plane_inverse * plane_gradient);
  residual_squares_ += squares - plane_gradient.dot(plane_inverse * plane_gradient);
  ++planes_;
  returns_ += used;
}

RingOffsets RingOffsetEstimator::solve() const {
  RingOffsets result = rings_;
  result.planes = planes_;
  result.returns = returns_;
  result.grazing_planes = grazing_planes_;
  const Eigen::Index rings = normal_.rows();
  const double prior = 1.0 / (options_.prior_sigma * options_.prior_sigma);
  const double dof = static_cast<double>(returns_) - 3.0 * planes_ - static_cast<double>(rings);
  if (!(dof > 0.0)) {
    result.offsets = Eigen::VectorXd::Zero(rings);
    result.sigmas = Eigen::VectorXd::Constant(rings, options_.prior_sigma);
    result.verdict = grazing_planes_ > 0 ? "not estimated: every room plane was seen only at grazing incidence"
                                         : "not estimated: no room plane (floor, wall, large furniture) with enough returns";
    return result;
  }
  // The returns' noise from the residuals: first with no offsets (an overestimate), then with them.
  // (A floor of 0.1 mm squared: noise-free returns would otherwise leave the prior no weight at all.)
  constexpr double kLeastVariance = 1e-8;
  double variance = std::max(residual_squares_ / dof, kLeastVariance), squares = residual_squares_;
  Eigen::MatrixXd information;
  for (int pass = 0; pass < 2; ++pass) {
    information = normal_ / variance + prior * Eigen::MatrixXd::Identity(rings, rings);
    result.offsets = information.ldlt().solve(gradient_ / variance);
    squares = residual_squares_ - 2.0 * gradient_.dot(result.offsets) + result.offsets.dot(normal_ * result.offsets);
    variance = std::max(squares / dof, kLeastVariance);
  }
  result.sigmas = information.inverse().diagonal().cwiseSqrt();
  result.rms = std::sqrt(std::max(squares, 0.0) / static_cast<double>(returns_));
  result.rms_as_measured = std::sqrt(std::max(residual_squares_, 0.0) / static_cast<double>(returns_));
  result.agreement = options_.plane_agreement;
  const double total = std::accumulate(plane_offset_information_.begin(), plane_offset_information_.end(), 0.0);
  if (total > 0.0) {
    int median = 0;
    for (double running = plane_offset_information_[0]; running < 0.5 * total;) running += plane_offset_information_[++median];
    result.common_offset = offsetOfBin(median);
    const int reach = static_cast<int>(std::lround(options_.plane_agreement / kOffsetBin));
    double agreeing = 0.0;
    for (int bin = std::max(0, median - reach); bin <= std::min(kOffsetBins - 1, median + reach); ++bin) agreeing += plane_offset_information_[bin];
    result.planes_agreeing = agreeing / total;
  }
  result.estimated = true;
  result.specification = options_.max_offset;
  Eigen::Index worst = 0;
  result.offsets.cwiseAbs().maxCoeff(&worst);
  char line[480];
  if (std::abs(result.offsets[worst]) > options_.max_offset) {
    result.beyond_specification = true;
    std::snprintf(line, sizeof(line),
                  "not applied yet: %s (the ring at %+.1f deg the most), beyond the +-%.0f mm a lidar's ranges are specified to: "
                  "either the room's planes do not fit a range offset per ring (bent or cluttered walls, %.1f mm rms off their "
                  "planes) or the driver's calibration is off; whether the room's planes agree on it and the board's held-out poses decide",
                  result.range().c_str(), result.elevations[worst] * 180.0 / M_PI, 1000 * options_.max_offset, 1000 * result.rms);
  } else {
    result.applied = true;
    std::snprintf(line, sizeof(line), "applied: every ring within +-%.0f mm", 1000 * options_.max_offset);
  }
  result.verdict = line;
  return result;
}

}  // namespace vocal
