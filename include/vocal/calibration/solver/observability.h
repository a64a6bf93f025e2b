#pragma once
// Which degrees of freedom the target planes constrain, per sensor and per sensor pair, before solving.

#include <map>
#include <string>
#include <vector>

#include "vocal/calibration/calibration_types.h"
#include "vocal/calibration/plane.h"

namespace vocal {

struct ObservabilityWarning {
  std::string sensor;  // "a" or "a + b" for a pair
  std::string dof;     // e.g. "translation along [0 0 1]", "rotation about [0 0 1]"
  double spread = 0.0; // smallest / largest singular value of the stacked normals
  std::string message;
};

// Normals of the planes a sensor (or a pair, on the poses both saw) observed: below `weak_spread`, the
// weakest direction of translation is reported; when every normal is nearly the same, also rotation
// about it. 2D lasers are checked through calibrateRig's line solver instead.
std::vector<ObservabilityWarning> checkObservability(const std::vector<SensorSpec>& sensors,
                                                     const std::vector<std::map<int, Plane>>& planes,
                                                     double weak_spread = 0.15);

}  // namespace vocal
