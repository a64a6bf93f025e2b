#include "vocal/tools/trajectory_report.h"

namespace vocal {

void printTrajectoryMetrics(std::FILE* out, const AteResult& ate, const RpeResult& rpe) {
  std::fprintf(out, "ate_rmse_m: %.6f\nate_median_m: %.6f\nate_max_m: %.6f\n", ate.rmse, ate.median, ate.max);
  std::fprintf(out, "rpe_trans_m_per_s: %.6f\nrpe_rot_deg_per_s: %.6f\n", rpe.translation_rmse_m_per_s,
               rpe.rotation_rmse_deg_per_s);
  std::fflush(out);
  std::fprintf(stderr, "(%zu poses associated for ATE, %zu pairs %.3g s apart for RPE)\n", ate.pairs, rpe.pairs,
               rpe.delta);
}

}  // namespace vocal
