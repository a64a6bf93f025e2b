#pragma once

#include <string>

#include "vocal/core/trajectory_evaluation.h"

namespace vocal {

// PNG with two panels: the aligned estimate and the ground truth seen from above (world x-y), and the
// position error over time. Throws InputError if the file cannot be written.
void writeTrajectoryPlot(const std::string& path, const AteResult& ate, const std::string& title);

}  // namespace vocal
