#pragma once
// A 6x6 least-squares system A x = b accumulated from residual rows, with the residual sum and count.
// Both backends reduce into the same 29 values: the 21 upper-triangle entries of A, 6 of b, the sum of
// squared residuals and the number of inliers.

#include "vocal/core/se3.h"

namespace vocal {

constexpr int kReductionValues = 29;

struct NormalEquations {
  Matrix6d A = Matrix6d::Zero();
  Vector6d b = Vector6d::Zero();
  // Of the residuals, each weighted by its noise weight where it has one (ICP's, DepthNoiseModel),
  // not by a robust weight (the photometric term's Huber weights): the term's variance at unit weight.
  double squared_residual_sum = 0.0;
  double count = 0.0;                 // inliers

  // Adds one row with Jacobian J, residual r and weight w (A += w J^T J, b -= w J^T r); a noise weight
  // (the inverse of the row's variance, relative) also weights its squared residual.
  void addRow(const Vector6d& J, double r, double w, bool noise_weight = false) {
    A.noalias() += w * J * J.transpose();
    b.noalias() -= w * r * J;
    squared_residual_sum += (noise_weight ? w * r : r) * r;
    count += 1.0;
  }

  NormalEquations& operator+=(const NormalEquations& other) {
    A += other.A;
    b += other.b;
    squared_residual_sum += other.squared_residual_sum;
    count += other.count;
    return *this;
  }

  // Every sum times `factor`: rows sampled one in `factor` then stand for all (OdometryBackend::
  // setSampledRows), as information, inlier counts and residual sums.
  NormalEquations& operator*=(double factor) {
    A *= factor;
    b *= factor;
    squared_residual_sum *= factor;
    count *= factor;
    return *this;
  }

  double rmse() const { return count > 0.0 ? std::sqrt(squared_residual_sum / count) : 0.0; }

  // Unpacks the 29-value layout produced by a reduction (upper triangle row by row, then b, then the
  // residual sum and count).
  static NormalEquations fromPacked(const double* values);
};

}  // namespace vocal
