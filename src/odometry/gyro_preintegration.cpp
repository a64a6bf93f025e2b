#include "vocal/odometry/gyro_preintegration.h"

#include <algorithm>

#include "vocal/core/se3.h"

namespace vocal {

namespace {
// The rate at `t` between the samples around it (the nearest at the ends).
Eigen::Vector3d rateAt(const std::vector<ImuSample>& samples, double t) {
  const auto after = std::lower_bound(samples.begin(), samples.end(), t, [](const ImuSample& s, double stamp) { return s.stamp < stamp; });
  if (after == samples.begin()) return after->angular_velocity;
  if (after == samples.end()) return samples.back().angular_velocity;
  const ImuSample& before = *(after - 1);
  const double span = after->stamp - before.stamp;
  const double alpha = span > 0.0 ? (t - before.stamp) / span : 0.0;
  return (1.0 - alpha) * before.angular_velocity + alpha * after->angular_velocity;
}
}  // namespace

GyroDelta preintegrateGyro(const std::vector<ImuSample>& samples, double t0, double t1, const Eigen::Vector3d& bias,
                           double gyro_noise_density, double max_gap) {
  GyroDelta delta;
  delta.seconds = t1 - t0;
  if (samples.empty() || !(t1 > t0)) return delta;
  auto first = std::upper_bound(samples.begin(), samples.end(), t0, [](double stamp, const ImuSample& s) { return stamp < s.stamp; });
  const auto last = std::lower_bound(samples.begin(), samples.end(), t1, [](const ImuSample& s, double stamp) { return s.stamp < stamp; });
  // The instants the rate is known at or interpolated to: t0, the samples strictly inside, t1.
  std::vector<double> knots{t0};
  for (auto it = first; it != last; ++it) knots.push_back(it->stamp);
  knots.push_back(t1);
  delta.samples = static_cast<int>(knots.size()) - 2;
  bool gaps_ok = true;
  const auto lo = first == samples.begin() ? first : first - 1;
  const auto hi = last == samples.end() ? samples.end() : last + 1;
  for (auto it = lo; it != hi && it + 1 != hi; ++it) gaps_ok = gaps_ok && (it + 1)->stamp - it->stamp <= max_gap;
  delta.complete = samples.front().stamp <= t0 && samples.back().stamp >= t1 && gaps_ok;
  const double variance_rate = gyro_noise_density * gyro_noise_density;  // rad^2/s: white rate noise integrated over time
  Eigen::Vector3d previous = rateAt(samples, t0) - bias;
  for (std::size_t k = 1; k < knots.size(); ++k) {
    const double dt = knots[k] - knots[k - 1];
    const Eigen::Vector3d rate = rateAt(samples, knots[k]) - bias;
    const Eigen::Matrix3d step = so3Exp(0.5 * (previous + rate) * dt);
    // Right perturbation: the earlier uncertainty seen from the later frame, plus this piece's noise.
    delta.covariance = step.transpose() * delta.covariance * step + variance_rate * dt * Eigen::Matrix3d::Identity();
    delta.rotation = delta.rotation * step;
    previous = rate;
  }
  return delta;
}

}  // namespace vocal
