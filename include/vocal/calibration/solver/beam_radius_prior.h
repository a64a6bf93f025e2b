#pragma once
// A 2D laser's beam radius (OutlinePointsResidual::withBeam, outline_view_residual.h) held loosely at
// none. Eigen only.

namespace vocal {

// The radius of a laser's beam as its scan ends see it, metres at the exit plus radians times the range:
// half its width where a beam returns from any part of it on the board (a SICK LMS1xx's beam is 8 mm +
// 15 mrad times the range across, by its manual), less where a beam partly off the board returns
// nothing or a mixed range (then below zero, too). The ends' reach past the board's edges over several
// ranges fixes it; the prior keeps it defined where they do not (a laser with few ends, all at one
// range). Blocks: the radius (metres, radians).
struct BeamRadiusPrior {
  double sigma_metres = 0.01, sigma_radians = 0.01;
  template <typename T>
  bool operator()(const T* beam, T* residual) const {
    residual[0] = beam[0] / T(sigma_metres);
    residual[1] = beam[1] / T(sigma_radians);
    return true;
  }
};

}  // namespace vocal
