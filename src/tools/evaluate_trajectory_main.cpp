// evaluate_trajectory GROUNDTRUTH ESTIMATE [--delta S] [--max-difference S] [--plot FILE.png]:
// the TUM benchmark's ATE and RPE, one `name: value` line each.

#include <cstdio>

#include "vocal/core/trajectory_evaluation.h"
#include "vocal/tools/command_line.h"
#include "vocal/tools/trajectory_plot.h"
#include "vocal/tools/trajectory_report.h"

namespace {
const char kUsage[] =
    "usage: evaluate_trajectory GROUNDTRUTH ESTIMATE [options]   (both in TUM format)\n"
    "  --delta S            RPE interval in seconds (default 1)\n"
    "  --max-difference S   stamp association tolerance (default 0.02, as the TUM tools)\n"
    "  --plot FILE.png      top view of the aligned trajectories and the error over time\n";

int run(const vocal::CommandLine& args) {
  const std::string truth_path = args.positional()[0];
  const std::string estimate_path = args.positional()[1];
  const vocal::Trajectory truth = vocal::readTumTrajectory(truth_path);
  const vocal::Trajectory estimate = vocal::readTumTrajectory(estimate_path);
  const double max_difference = args.number("max-difference", 0.02);
  const vocal::AteResult ate = vocal::computeAte(truth, estimate, max_difference);
  const vocal::RpeResult rpe = vocal::computeRpe(truth, estimate, args.number("delta", 1.0), max_difference);
  vocal::printTrajectoryMetrics(stdout, ate, rpe);
  if (args.has("plot")) {
    vocal::writeTrajectoryPlot(args.text("plot", ""), ate, estimate_path + " vs " + truth_path);
  }
  return 0;
}
}  // namespace

int main(int argc, char** argv) {
  return vocal::runTool("evaluate_trajectory", kUsage, run, argc, argv, {"delta", "max-difference", "plot"}, {}, 2);
}
