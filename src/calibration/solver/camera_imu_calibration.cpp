#include "vocal/calibration/solver/camera_imu_calibration.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <memory>
#include <sstream>

#include <Eigen/SVD>
#include <ceres/ceres.h>

#include "vocal/calibration/solver/cumulative_bspline.h"
#include "vocal/calibration/solver/imu_sample_residual.h"
#include "vocal/calibration/solver/spline_camera_view_residual.h"
#include "vocal/calibration/solver/spline_corner_residual.h"
#include "vocal/core/errors.h"
#include "vocal/core/se3.h"

namespace vocal {

CameraImuView cameraImuView(double stamp, const PatternObservation& seen, std::vector<Eigen::Vector2d> corners) {
  if (!seen.corners_left_out.empty()) corners.clear();
  return CameraImuView{stamp, seen.plane, std::move(corners), seen.reprojection_rms_px};
}

namespace {

constexpr int kLeastViews = 20;
constexpr int kLeastImuSamples = 100;

// The camera's turn between two consecutive views as a body rate (camera frame) at their middle time.
struct CameraRate {
  double start = 0.0, end = 0.0;  // camera clock
  Eigen::Vector3d rate = Eigen::Vector3d::Zero();
};

std::vector<CameraRate> cameraRates(const std::vector<CameraImuView>& views) {
  // Consecutive views only: across a gap (frames without the board) the turn is not a rate.
  double typical = 0.0;
  {
    std::vector<double> gaps;
    for (std::size_t k = 1; k < views.size(); ++k) gaps.push_back(views[k].stamp - views[k - 1].stamp);
    std::nth_element(gaps.begin(), gaps.begin() + gaps.size() / 2, gaps.end());
    typical = gaps[gaps.size() / 2];
  }
  std::vector<CameraRate> rates;
  for (std::size_t k = 1; k < views.size(); ++k) {
    const double dt = views[k].stamp - views[k - 1].stamp;
    if (dt > 1.5 * typical) continue;
    // board <- camera at each view; the body rate is log(R_k-1^T R_k) / dt in the camera frame.
    const Eigen::Matrix3d before = views[k - 1].board.sensor_from_pattern.linear().transpose();
    const Eigen::Matrix3d after = views[k].board.sensor_from_pattern.linear().transpose();
    rates.push_back({views[k - 1].stamp, views[k].stamp, so3Log(before.transpose() * after) / dt});
  }
  return rates;
}

// The gyro's mean over [start, end) of its own clock, from prefix sums over the samples.
class GyroMeans {
 public:
  explicit GyroMeans(const std::vector<ImuSample>& imu) : imu_(imu), sums_(imu.size() + 1, Eigen::Vector3d::Zero()) {
    for (std::size_t i = 0; i < imu.size(); ++i) sums_[i + 1] = sums_[i] + imu[i].angular_velocity;
  }
  // False when the interval holds no sample.
  bool mean(double start, double end, Eigen::Vector3d* out) const {
    const auto first = std::lower_bound(imu_.begin(), imu_.end(), start, [](const ImuSample& s, double t) { return s.stamp < t; });
    const auto last = std::lower_bound(imu_.begin(), imu_.end(), end, [](const ImuSample& s, double t) { return s.stamp < t; });
    const long count = last - first;
    if (count <= 0) return false;
    *out = (sums_[last - imu_.begin()] - sums_[first - imu_.begin()]) / static_cast<double>(count);
    return true;
  }

 private:
  const std::vector<ImuSample>& imu_;
  std::vector<Eigen::Vector3d> sums_;
};

// Correlation of the camera's and the gyro's angular speeds with the gyro read `offset` later; NaN with
// too few intervals inside the IMU's span.
double speedCorrelation(const std::vector<CameraRate>& rates, const GyroMeans& gyro, double offset) {
  double sx = 0, sy = 0, sxx = 0, syy = 0, sxy = 0;
  int n = 0;
  for (const CameraRate& r : rates) {
    Eigen::Vector3d g;
    if (!gyro.mean(r.start + offset, r.end + offset, &g)) continue;
    const double x = r.rate.norm(), y = g.norm();
    sx += x, sy += y, sxx += x * x, syy += y * y, sxy += x * y;
    ++n;
  }
  if (n < kLeastViews / 2) return std::numeric_limits<double>::quiet_NaN();
  const double cov = sxy / n - sx / n * sy / n;
  const double vx = sxx / n - sx / n * sx / n, vy = syy / n - sy / n * sy / n;
  if (vx <= 0.0 || vy <= 0.0) return std::numeric_limits<double>::quiet_NaN();
  return cov / std::sqrt(vx * vy);
}

// Rotation R (camera <- IMU) and gyro bias b with camera rate = R (gyro - b), least squares (Kabsch, the
// bias alternated with it). Returns the misfit: the residual rates' RMS over the camera rates'.
double alignRates(const std::vector<CameraRate>& rates, const GyroMeans& gyro, double offset, Eigen::Matrix3d* camera_from_imu,
                Eigen::Vector3d* bias) {
  std::vector<Eigen::Vector3d> cam, imu;
  for (const CameraRate& r : rates) {
    Eigen::Vector3d g;
    if (!gyro.mean(r.start + offset, r.end + offset, &g)) continue;
    cam.push_back(r.rate);
    imu.push_back(g);
  }
  bias->setZero();
  for (int pass = 0; pass < 4; ++pass) {
    Eigen::Matrix3d h = Eigen::Matrix3d::Zero();
    for (std::size_t i = 0; i < cam.size(); ++i) h += (imu[i] - *bias) * cam[i].transpose();
    const Eigen::JacobiSVD<Eigen::Matrix3d> svd(h, Eigen::ComputeFullU | Eigen::ComputeFullV);
    Eigen::Matrix3d d = Eigen::Matrix3d::Identity();
    d(2, 2) = (svd.matrixV() * svd.matrixU().transpose()).determinant() < 0 ? -1.0 : 1.0;
    *camera_from_imu = svd.matrixV() * d * svd.matrixU().transpose();
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (std::size_t i = 0; i < cam.size(); ++i) sum += imu[i] - camera_from_imu->transpose() * cam[i];
    *bias = sum / static_cast<double>(cam.size());
  }
  double left = 0.0, total = 0.0;
  for (std::size_t i = 0; i < cam.size(); ++i) {
    left += (cam[i] - *camera_from_imu * (imu[i] - *bias)).squaredNorm();
    total += cam[i].squaredNorm();
  }
  return std::sqrt(left / total);
}

// Why the rig's turns cannot fix the rotation between camera and IMU; empty when they can. From the
// gyro (the camera's rates, differences of PnP poses, carry their noise on every axis), its mean taken off.
std::string motionProblem(const std::vector<ImuSample>& imu, double min_axis_rate) {
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const ImuSample& s : imu) mean += s.angular_velocity / static_cast<double>(imu.size());
  Eigen::Matrix3d second = Eigen::Matrix3d::Zero();
  for (const ImuSample& s : imu) second += (s.angular_velocity - mean) * (s.angular_velocity - mean).transpose();
  second /= static_cast<double>(imu.size());
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(second);
  const Eigen::Vector3d axis_rates = eigen.eigenvalues().cwiseMax(0.0).cwiseSqrt();  // ascending
  std::ostringstream out;
  out.precision(3);
  if (axis_rates[2] < min_axis_rate) {
    out << "the camera never turns (the gyro reads " << axis_rates[2] << " rad/s RMS about any axis, at least " << min_axis_rate
        << " is needed): the rotation between camera and IMU and the lever arm are not fixed; turn the rig about all three axes while waving it";
  } else if (axis_rates[1] < min_axis_rate) {
    const Eigen::Vector3d axis = eigen.eigenvectors().col(2);
    out << "the camera turns about one axis only (the gyro reads " << axis_rates[2] << " rad/s RMS about IMU axis [" << axis.x() << ", "
        << axis.y() << ", " << axis.z() << "], " << axis_rates[1] << " about the next, at least " << min_axis_rate
        << " is needed): the rotation about it is not fixed; turn the rig about all three axes (roll, pitch and yaw) while waving it";
  }
  return out.str();
}

// The camera's pose in the board frame at camera time t, between the views either side (clamped at the ends).
Eigen::Isometry3d boardFromCameraAt(const std::vector<CameraImuView>& views, double t) {
  const auto next = std::lower_bound(views.begin(), views.end(), t, [](const CameraImuView& v, double s) { return v.stamp < s; });
  if (next == views.begin()) return views.front().board.sensor_from_pattern.inverse();
  if (next == views.end()) return views.back().board.sensor_from_pattern.inverse();
  const CameraImuView& before = *(next - 1);
  const double alpha = (t - before.stamp) / (next->stamp - before.stamp);
  return interpolatePose(before.board.sensor_from_pattern.inverse(), next->board.sensor_from_pattern.inverse(), alpha);
}

void checkInput(const std::vector<CameraImuView>& views, const std::vector<ImuSample>& imu) {
  if (static_cast<int>(views.size()) < kLeastViews) {
    throw InputError("camera-IMU calibration: " + std::to_string(views.size()) + " camera views of the board, at least " +
                     std::to_string(kLeastViews) + " are needed (wave the rig before the board for 1-3 minutes)");
  }
  if (static_cast<int>(imu.size()) < kLeastImuSamples) {
    throw InputError("camera-IMU calibration: " + std::to_string(imu.size()) + " IMU samples, at least " +
                     std::to_string(kLeastImuSamples) + " are needed");
  }
  for (std::size_t k = 1; k < views.size(); ++k) {
    if (!(views[k].stamp > views[k - 1].stamp)) {
      throw InputError("camera-IMU calibration: camera view " + std::to_string(k) + "'s stamp is not after the one before");
    }
  }
  for (std::size_t i = 1; i < imu.size(); ++i) {
    if (!(imu[i].stamp > imu[i - 1].stamp)) {
      throw InputError("camera-IMU calibration: IMU sample " + std::to_string(i) + "'s stamp is not after the one before");
    }
  }
}

// A checkerboard's corners are found either way round: each view turned to the way nearer the one before
// (a hand does not turn the rig half a turn about the board's normal between two frames).
std::vector<CameraImuView> numberedAlike(const std::vector<CameraImuView>& views, int* turned) {
  std::vector<CameraImuView> out = views;
  for (std::size_t k = 1; k < out.size(); ++k) {
    const Eigen::Matrix3d before = out[k - 1].board.sensor_from_pattern.linear();
    const PlaneMeasurement other = turnedHalfway(out[k].board);
    const double as_found = so3Log(before.transpose() * out[k].board.sensor_from_pattern.linear()).norm();
    const double as_turned = so3Log(before.transpose() * other.sensor_from_pattern.linear()).norm();
    // A board found the other way round is half a turn away; a view nearer than two thirds of that is
    // another matter (withoutSpikes).
    if (as_found > 2.0 && as_turned < as_found) {
      out[k].board = other;
      // Half a turn about the centred pattern's normal takes corner i to corner n - 1 - i.
      std::reverse(out[k].corners.begin(), out[k].corners.end());
      ++*turned;
    }
  }
  return out;
}

// Views whose board turned away and straight back between their neighbours (a planar board's PnP has a
// second, mirrored solution where it is seen small or square on, with as small a reprojection error):
// left out. A spike: the way through it longer than the neighbours' direct turn by over `threshold` (on a
// smooth motion the two are equal to second order).
std::vector<CameraImuView> withoutSpikes(const std::vector<CameraImuView>& views, int* left_out) {
  const auto turn = [&](std::size_t a, std::size_t b) {
    return so3Log(views[a].board.sensor_from_pattern.linear().transpose() * views[b].board.sensor_from_pattern.linear()).norm();
  };
  std::vector<double> turns;
  for (std::size_t k = 1; k < views.size(); ++k) turns.push_back(turn(k - 1, k));
  std::nth_element(turns.begin(), turns.begin() + turns.size() / 2, turns.end());
  const double threshold = std::max(0.15, 5.0 * turns[turns.size() / 2]);
  std::vector<CameraImuView> out;
  for (std::size_t k = 0; k < views.size(); ++k) {
    if (k > 0 && k + 1 < views.size() && turn(k - 1, k) + turn(k, k + 1) - turn(k - 1, k + 1) > threshold) {
      ++*left_out;
      continue;
    }
    out.push_back(views[k]);
  }
  return out;
}

// The IMU-clock span where the rig was waved: from the first to the last 1 s window whose gyro turns (its
// RMS about the window's mean over `min_rate`), half a window either side. False when none turns.
bool wavedSpan(const std::vector<ImuSample>& imu, double min_rate, double* start, double* end) {
  bool any = false;
  for (std::size_t first = 0; first < imu.size();) {
    std::size_t last = first;
    while (last < imu.size() && imu[last].stamp < imu[first].stamp + 1.0) ++last;
    Eigen::Vector3d mean = Eigen::Vector3d::Zero();
    for (std::size_t i = first; i < last; ++i) mean += imu[i].angular_velocity / static_cast<double>(last - first);
    double square = 0.0;
    for (std::size_t i = first; i < last; ++i) square += (imu[i].angular_velocity - mean).squaredNorm() / static_cast<double>(last - first);
    if (last - first > 2 && std::sqrt(square) > min_rate) {
      if (!any) *start = imu[first].stamp - 0.5;
      *end = imu[last - 1].stamp + 0.5;
      any = true;
    }
    first = last;
  }
  return any;
}

struct Unknowns {
  SplineKnots knots;
  std::vector<Eigen::Quaterniond> rotations;
  std::vector<Eigen::Vector3d> positions;
  std::vector<Eigen::Vector3d> gyro_biases, accel_biases;
  double bias_start = 0.0, bias_spacing = 1.0;
  Eigen::Vector3d down = Eigen::Vector3d::UnitZ();
  Eigen::Quaterniond camera_q = Eigen::Quaterniond::Identity();
  Eigen::Vector3d camera_t = Eigen::Vector3d::Zero();
  double time_offset = 0.0;

  // Segment i's four control rotations and four positions, as the residuals take them.
  std::array<const double*, 4> rotationsOf(int i) const {
    return {rotations[i].coeffs().data(), rotations[i + 1].coeffs().data(), rotations[i + 2].coeffs().data(), rotations[i + 3].coeffs().data()};
  }
  std::array<const double*, 4> positionsOf(int i) const {
    return {positions[i].data(), positions[i + 1].data(), positions[i + 2].data(), positions[i + 3].data()};
  }
  std::vector<double*> segmentBlocks(int i) {
    std::vector<double*> blocks;
    for (int k = 0; k < 4; ++k) blocks.push_back(rotations[i + k].coeffs().data());
    for (int k = 0; k < 4; ++k) blocks.push_back(positions[i + k].data());
    return blocks;
  }
};

}  // namespace

CameraImuResult calibrateCameraImu(const std::vector<CameraImuView>& found, const std::vector<ImuSample>& imu, const ImuNoise& noise,
                                   const CameraImuOptions& options) {
  checkInput(found, imu);
  CameraImuResult result;
  // Only the waved part: where the rig rests (set down, or held still while a board was moved before it
  // for the other sensors' still poses) its views are not of a fixed board.
  std::vector<CameraImuView> waved;
  double waved_start = imu.front().stamp, waved_end = imu.back().stamp;
  if (wavedSpan(imu, options.min_axis_rate, &waved_start, &waved_end)) {
    for (const CameraImuView& v : found) {
      if (v.stamp >= waved_start - options.max_time_offset && v.stamp <= waved_end + options.max_time_offset) waved.push_back(v);
    }
    result.views_at_rest = static_cast<int>(found.size() - waved.size());
  } else {
    waved = found;  // the motion check below says it never turns
  }
  checkInput(waved, imu);
  const std::vector<CameraImuView> views = withoutSpikes(numberedAlike(waved, &result.turned_views), &result.left_out_views);

  // 1. Closed forms: the time offset from the angular speeds, the rotation (and gyro bias) from the rates.
  const std::vector<CameraRate> rates = cameraRates(views);
  if (static_cast<int>(rates.size()) < kLeastViews) {
    throw InputError("camera-IMU calibration: " + std::to_string(rates.size()) +
                     " pairs of consecutive camera views, at least " + std::to_string(kLeastViews) +
                     " are needed (the board must stay in view for most frames)");
  }
  std::vector<ImuSample> turning;
  for (const ImuSample& s : imu)
    if (s.stamp >= waved_start && s.stamp <= waved_end) turning.push_back(s);
  const std::string problem = motionProblem(turning.size() > 2 ? turning : imu, options.min_axis_rate);
  if (!problem.empty()) throw InputError("camera-IMU calibration: " + problem);
  const GyroMeans gyro(imu);
  const double step = 0.001;
  const int steps = static_cast<int>(std::ceil(options.max_time_offset / step));
  std::vector<double> scores(2 * steps + 1, std::numeric_limits<double>::quiet_NaN());
  int best = -1;
  for (int i = 0; i <= 2 * steps; ++i) {
    scores[i] = speedCorrelation(rates, gyro, (i - steps) * step);
    if (std::isfinite(scores[i]) && (best < 0 || scores[i] > scores[best])) best = i;
  }
  if (best < 0 || scores[best] < 0.5) {
    std::ostringstream out;
    out << "camera-IMU calibration: the camera's and the gyro's angular speeds do not correlate at any time offset within +-"
        << options.max_time_offset << " s (best " << (best < 0 ? 0.0 : scores[best])
        << "): do the two streams come from the same rig and the same minutes?";
    throw InputError(out.str());
  }
  double offset = (best - steps) * step;
  if (best > 0 && best < 2 * steps && std::isfinite(scores[best - 1]) && std::isfinite(scores[best + 1])) {
    const double a = scores[best - 1], b = scores[best], c = scores[best + 1];
    const double curvature = a - 2 * b + c;
    if (curvature < 0) offset += 0.5 * (a - c) / curvature * step;
  }
  result.initial_time_offset = offset;
  result.angular_speed_correlation = scores[best];
  Eigen::Matrix3d camera_from_imu;
  Eigen::Vector3d gyro_bias;
  const double misfit = alignRates(rates, gyro, offset, &camera_from_imu, &gyro_bias);
  if (misfit > 0.5) {
    std::ostringstream out;
    out.precision(3);
    out << "camera-IMU calibration: the gyro's rates do not follow the camera's turns at any rotation between them (what is left is "
        << misfit * 100 << " % of the camera's rates, best time offset " << offset
        << " s): do the two streams come from the same rig and the same minutes?";
    throw InputError(out.str());
  }
  result.initial_rotation = camera_from_imu.transpose();

  // 2. The spline over the IMU-clock span both streams cover, started from the camera's poses.
  Unknowns x;
  x.time_offset = offset;
  x.camera_q = Eigen::Quaterniond(camera_from_imu.transpose());
  const double margin = options.max_time_offset;
  const double start = std::max(imu.front().stamp, views.front().stamp + offset - margin);
  const double end = std::min(imu.back().stamp, views.back().stamp + offset + margin);
  if (!(end - start > 10 * options.knot_spacing)) {
    throw InputError("camera-IMU calibration: the camera's views and the IMU's samples do not overlap in time (views " +
                     std::to_string(views.front().stamp) + "-" + std::to_string(views.back().stamp) + " s, IMU " +
                     std::to_string(imu.front().stamp) + "-" + std::to_string(imu.back().stamp) + " s)");
  }
  x.knots.start = start;
  x.knots.spacing = options.knot_spacing;
  x.knots.control_points = static_cast<int>(std::ceil((end - start) / options.knot_spacing)) + 3;
  const Eigen::Isometry3d camera_from_body = Eigen::Isometry3d(camera_from_imu);
  for (int k = 0; k < x.knots.control_points; ++k) {
    const Eigen::Isometry3d board_from_body = boardFromCameraAt(views, x.knots.controlPointTime(k) - offset) * camera_from_body;
    Eigen::Quaterniond q(board_from_body.linear());
    // Neighbours on the same hemisphere (the spline takes the shorter way anyway; this keeps the blocks tidy).
    if (k > 0 && q.coeffs().dot(x.rotations.back().coeffs()) < 0) q.coeffs() = -q.coeffs();
    x.rotations.push_back(q);
    x.positions.push_back(board_from_body.translation());
  }
  // Gravity: the body's mean acceleration over a waved session is about zero, so the specific force's
  // mean in the board frame is gravity's opposite.
  Eigen::Vector3d mean_force = Eigen::Vector3d::Zero();
  for (const ImuSample& s : imu) {
    if (s.stamp < start || s.stamp >= end) continue;
    mean_force += boardFromCameraAt(views, s.stamp - offset).linear() * camera_from_imu * s.linear_acceleration;
  }
  x.down = -mean_force.normalized();
  x.bias_spacing = options.bias_knot_spacing;
  x.bias_start = start;
  const int bias_knots = static_cast<int>(std::ceil((end - start) / options.bias_knot_spacing)) + 1;
  x.gyro_biases.assign(bias_knots, gyro_bias);
  x.accel_biases.assign(bias_knots, Eigen::Vector3d::Zero());

  // 3. One Ceres problem.
  ceres::Problem problem_graph;
  for (int k = 0; k < x.knots.control_points; ++k) {
    problem_graph.AddParameterBlock(x.rotations[k].coeffs().data(), 4, new ceres::EigenQuaternionManifold());
    problem_graph.AddParameterBlock(x.positions[k].data(), 3);
  }
  const double rate = imuRate(imu);
  const double gyro_sigma = noise.gyro_noise_density * std::sqrt(rate);
  const double accel_sigma = noise.accel_noise_density * std::sqrt(rate);
  // Each sample's term and its blocks, kept for its residual once solved.
  std::vector<std::pair<const ceres::CostFunction*, std::vector<double*>>> imu_terms;
  for (const ImuSample& s : imu) {
    if (s.stamp < start || s.stamp >= end) continue;
    const SplineSegment seg = x.knots.segmentAt(s.stamp);
    const double b = (s.stamp - x.bias_start) / x.bias_spacing;
    const int b0 = std::min(static_cast<int>(std::floor(b)), bias_knots - 2);
    auto* cost = new ceres::AutoDiffCostFunction<ImuSampleResidual, 6, 4, 4, 4, 4, 3, 3, 3, 3, 3, 3, 3, 3, 3>(
        new ImuSampleResidual(s.angular_velocity, s.linear_acceleration, seg.u, x.knots.spacing, b - b0, gyro_sigma, accel_sigma,
                              options.gravity));
    std::vector<double*> blocks = x.segmentBlocks(seg.index);
    blocks.insert(blocks.end(), {x.gyro_biases[b0].data(), x.gyro_biases[b0 + 1].data(), x.accel_biases[b0].data(),
                                 x.accel_biases[b0 + 1].data(), x.down.data()});
    problem_graph.AddResidualBlock(cost, nullptr, blocks);
    imu_terms.emplace_back(cost, std::move(blocks));
  }
  result.imu_samples = static_cast<int>(imu_terms.size());
  problem_graph.SetManifold(x.down.data(), new ceres::SphereManifold<3>());
  for (int k = 0; k + 1 < bias_knots; ++k) {
    const double interval = std::sqrt(x.bias_spacing);
    problem_graph.AddResidualBlock(new ceres::AutoDiffCostFunction<BiasRandomWalkResidual, 3, 3, 3>(
                                       new BiasRandomWalkResidual(noise.gyro_bias_random_walk * interval)),
                                   nullptr, x.gyro_biases[k].data(), x.gyro_biases[k + 1].data());
    problem_graph.AddResidualBlock(new ceres::AutoDiffCostFunction<BiasRandomWalkResidual, 3, 3, 3>(
                                       new BiasRandomWalkResidual(noise.accel_bias_random_walk * interval)),
                                   nullptr, x.accel_biases[k].data(), x.accel_biases[k + 1].data());
  }
  problem_graph.AddParameterBlock(x.camera_q.coeffs().data(), 4, new ceres::EigenQuaternionManifold());
  problem_graph.AddParameterBlock(x.camera_t.data(), 3);
  problem_graph.AddParameterBlock(&x.time_offset, 1);
  const std::vector<Eigen::Vector3d> corners = options.camera_model ? options.camera_model->pattern.corners() : std::vector<Eigen::Vector3d>();
  // A view is kept where its time on the IMU's clock stays inside the spline whatever the offset becomes.
  std::vector<const CameraImuView*> used;
  for (const CameraImuView& v : views) {
    const double t = v.stamp + offset;
    if (t < start + margin * 0.5 || t >= end - margin * 0.5) continue;
    const SplineSegment seg = x.knots.segmentAt(t);
    const int i = seg.index;
    const double segment_start = x.knots.start + i * x.knots.spacing;
    ceres::CostFunction* cost = nullptr;
    ceres::LossFunction* loss = nullptr;
    // Robust: a view PnP placed on its mirrored solution at a run's start has no neighbours to show it.
    if (options.camera_model && v.corners.size() == corners.size() && !corners.empty()) {
      const int residuals = static_cast<int>(2 * corners.size());
      cost = new ceres::AutoDiffCostFunction<SplineCornerResidual, ceres::DYNAMIC, 4, 4, 4, 4, 3, 3, 3, 3, 4, 3, 1>(
          new SplineCornerResidual(v.corners, corners, options.camera_model->camera, options.camera_model->lens,
                                   std::max(v.pixel_sigma, 0.05), v.stamp, segment_start, x.knots.spacing),
          residuals);
      loss = new ceres::HuberLoss(3.0 * std::sqrt(static_cast<double>(residuals)));
      ++result.views_by_corners;
    } else {
      cost = new ceres::AutoDiffCostFunction<SplineCameraViewResidual, 6, 4, 4, 4, 4, 3, 3, 3, 3, 4, 3, 1>(
          new SplineCameraViewResidual(v.board, v.stamp, segment_start, x.knots.spacing));
      loss = new ceres::CauchyLoss(3.0);
    }
    std::vector<double*> blocks = x.segmentBlocks(i);
    blocks.insert(blocks.end(), {x.camera_q.coeffs().data(), x.camera_t.data(), &x.time_offset});
    problem_graph.AddResidualBlock(cost, loss, blocks);
    used.push_back(&v);
  }
  result.views = static_cast<int>(used.size());
  if (result.views < kLeastViews) {
    throw InputError("camera-IMU calibration: " + std::to_string(result.views) + " camera views fall within the IMU's samples, at least " +
                     std::to_string(kLeastViews) + " are needed");
  }

  ceres::Solver::Options solver_options;
  solver_options.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  solver_options.max_num_iterations = options.max_iterations;
  solver_options.num_threads = options.threads;
  solver_options.function_tolerance = 1e-10;
  solver_options.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(solver_options, &problem_graph, &summary);
  result.iterations = static_cast<int>(summary.iterations.size());

  result.camera_in_imu = Eigen::Isometry3d::Identity();
  result.camera_in_imu.linear() = x.camera_q.normalized().toRotationMatrix();
  result.camera_in_imu.translation() = x.camera_t;
  result.time_offset = x.time_offset;
  result.gravity_in_board = x.down * options.gravity;
  for (int k = 0; k < bias_knots; ++k) {
    result.gyro_bias += x.gyro_biases[k] / bias_knots;
    result.accel_bias += x.accel_biases[k] / bias_knots;
  }

  // Residuals per kind, unwhitened.
  double gyro_sq = 0, accel_sq = 0;
  for (const auto& [cost, blocks] : imu_terms) {
    double out[6];
    cost->Evaluate(blocks.data(), out, nullptr);
    for (int a = 0; a < 3; ++a) {
      gyro_sq += (out[a] * gyro_sigma) * (out[a] * gyro_sigma);
      accel_sq += (out[3 + a] * accel_sigma) * (out[3 + a] * accel_sigma);
    }
  }
  result.gyro_rms = std::sqrt(gyro_sq / (3.0 * result.imu_samples));
  result.accel_rms = std::sqrt(accel_sq / (3.0 * result.imu_samples));
  double view_t_sq = 0, view_r_sq = 0;
  for (const CameraImuView* v : used) {
    const SplineSegment seg = x.knots.segmentAt(v->stamp + x.time_offset);
    const int i = seg.index;
    Eigen::Quaterniond rotation;
    Eigen::Vector3d translation;
    cameraFromBoardAt<double>(x.rotationsOf(i), x.positionsOf(i), x.camera_q.coeffs().data(), x.camera_t.data(), seg.u, x.knots.spacing,
                              &rotation, &translation);
    const Eigen::Isometry3d predicted = poseFromTranslationQuaternion(translation, rotation);
    const Eigen::Isometry3d error = v->board.sensor_from_pattern.inverse() * predicted;
    view_t_sq += (predicted.translation() - v->board.sensor_from_pattern.translation()).squaredNorm();
    view_r_sq += so3Log(error.linear()).squaredNorm();
  }
  result.view_translation_rms = std::sqrt(view_t_sq / used.size());
  result.view_rotation_rms = std::sqrt(view_r_sq / used.size());

  // 4. Standard deviations of the extrinsic and the offset from the solver's covariance.
  ceres::Covariance::Options covariance_options;
  covariance_options.algorithm_type = ceres::SPARSE_QR;
  covariance_options.num_threads = options.threads;
  ceres::Covariance covariance(covariance_options);
  const std::vector<std::pair<const double*, const double*>> blocks = {
      {x.camera_q.coeffs().data(), x.camera_q.coeffs().data()},
      {x.camera_t.data(), x.camera_t.data()},
      {&x.time_offset, &x.time_offset}};
  std::ostringstream withheld;
  if (!summary.IsSolutionUsable()) {
    withheld << "the solver failed (" << summary.message << ")";
  } else if (covariance.Compute(blocks, &problem_graph)) {
    double rotation_cov[9], translation_cov[9], offset_var = 0.0;
    covariance.GetCovarianceBlockInTangentSpace(x.camera_q.coeffs().data(), x.camera_q.coeffs().data(), rotation_cov);
    covariance.GetCovarianceBlock(x.camera_t.data(), x.camera_t.data(), translation_cov);
    covariance.GetCovarianceBlock(&x.time_offset, &x.time_offset, &offset_var);
    // Ceres's quaternion tangent d turns by exp(2 d) on the left: the rotation vector is twice it, in the
    // IMU frame (camera_q maps camera to IMU).
    for (int a = 0; a < 3; ++a) {
      result.sigma[a] = std::sqrt(std::max(0.0, translation_cov[4 * a]));
      result.sigma[3 + a] = 2.0 * std::sqrt(std::max(0.0, rotation_cov[4 * a]));
    }
    result.time_offset_sigma = std::sqrt(std::max(0.0, offset_var));
    const double worst_t = result.sigma.head<3>().maxCoeff(), worst_r = result.sigma.tail<3>().maxCoeff();
    withheld.precision(3);
    if (worst_t > options.max_translation_sigma || worst_r > options.max_rotation_sigma) {
      withheld << "the motion leaves the camera's pose in the IMU uncertain (" << worst_t * 1000 << " mm / " << worst_r * 1000
               << " mrad standard deviation, at most " << options.max_translation_sigma * 1000 << " / " << options.max_rotation_sigma * 1000
               << "): wave the rig longer, faster and about all three axes, and move it along all three";
    } else if (result.time_offset_sigma > options.max_time_offset_sigma) {
      withheld << "the time offset is uncertain (" << result.time_offset_sigma * 1000 << " ms standard deviation, at most "
               << options.max_time_offset_sigma * 1000 << "): wave the rig faster";
    }
  } else {
    withheld << "the solution's covariance could not be computed: the motion does not fix every unknown";
  }
  result.withheld = withheld.str();
  return result;
}

}  // namespace vocal
