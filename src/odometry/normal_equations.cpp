#include "vocal/odometry/normal_equations.h"

namespace vocal {

NormalEquations NormalEquations::fromPacked(const double* values) {
  NormalEquations system;
  int k = 0;
  for (int row = 0; row < 6; ++row) {
    for (int col = row; col < 6; ++col) {
      system.A(row, col) = system.A(col, row) = values[k++];
    }
  }
  for (int row = 0; row < 6; ++row) system.b[row] = values[k++];
  system.squared_residual_sum = values[k++];
  system.count = values[k++];
  return system;
}

}  // namespace vocal
