#pragma once
// A free joint origin's correction (JointDescription::free_origin) in the calibration graphs: the model's
// origin as a prior, within JointTolerances' origin sigmas. Where the session fixes a part of the origin
// the views outweigh it; where it does not, the prior holds that part at the model's value (and says so,
// by a standard deviation near the prior's).

namespace vocal {

// One block of 6 (w, dt): the rotation vector (radians) and the shift (metres) of jointOriginCorrected.
struct JointOriginPrior {
  double rotation_sigma, translation_sigma;

  template <typename T>
  bool operator()(const T* correction, T* residual) const {
    for (int k = 0; k < 3; ++k) residual[k] = correction[k] / T(rotation_sigma);
    for (int k = 3; k < 6; ++k) residual[k] = correction[k] / T(translation_sigma);
    return true;
  }
};

}  // namespace vocal
