#pragma once
// A still pose's joint readings in the arm's graph (hand_eye_calibration.h): each reading's correction
// (its true position less the reading) within the reading's sigma.

#include <cstddef>
#include <vector>

namespace vocal {

// One block and one residual per joint read; the caller puts the pose's residuals under one robust loss,
// so a pose whose readings do not fit counts as poor as a whole.
struct ReadingCorrectionsResidual {
  std::vector<double> sigmas;  // radians (metres for a prismatic joint)

  template <typename T>
  bool operator()(T const* const* blocks, T* residual) const {
    for (std::size_t i = 0; i < sigmas.size(); ++i) residual[i] = blocks[i][0] / T(sigmas[i]);
    return true;
  }
};

}  // namespace vocal
