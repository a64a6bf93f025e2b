#pragma once
// The noise of a depth camera's measurement along its ray: sigma(z)^2 = floor^2 + (quadratic z^2)^2.
// Structured light and stereo measure disparity, so their depth noise grows with the square of the
// depth (Khoshelham and Elberink 2012; Nguyen et al. 2012); on the real TUM freiburg1 Kinect frames
// the residuals of quadratic surfaces fitted in 7x7 patches give 1.0 mm * z^2 above a 0.5 mm floor
// on all three sequences (bench/depth_noise.py, docs/benchmarks.md). ICP can weight each
// point-to-plane pair by it: a pair 3 m away has 65 times the variance of one at 1 m.

namespace vocal {

struct DepthNoiseModel {
  DepthNoiseModel(double floor, double quadratic)
      : floor_squared(static_cast<float>(floor * floor)),
        quadratic_squared(static_cast<float>(quadratic * quadratic)),
        variance_at_one_metre(2.0f * floor_squared + quadratic_squared * 2.0f) {}

  // The weight of a point-to-plane pair of a current point at depth z_current and a reference point
  // at z_reference: the variance of a pair at 1 m over this pair's (both points' noise adds). 1 at
  // 1 m, and 1 everywhere when quadratic is 0 (the same expression, so exactly 1).
  float icpWeight(float z_current, float z_reference) const {
    const float a = z_current * z_current, b = z_reference * z_reference;
    return variance_at_one_metre / (2.0f * floor_squared + quadratic_squared * (a * a + b * b));
  }

  float floor_squared, quadratic_squared, variance_at_one_metre;
};

}  // namespace vocal
