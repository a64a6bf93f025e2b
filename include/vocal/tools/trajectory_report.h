#pragma once

#include <cstdio>

#include "vocal/core/trajectory_evaluation.h"

namespace vocal {

// Prints the evaluate_trajectory lines (`ate_rmse_m: X` ... `rpe_rot_deg_per_s: X`) to `out`, and the
// pair counts to stderr.
void printTrajectoryMetrics(std::FILE* out, const AteResult& ate, const RpeResult& rpe);

}  // namespace vocal
