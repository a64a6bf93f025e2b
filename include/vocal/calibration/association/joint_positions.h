#pragma once
// The joints' positions at each still pose, for the sensors behind them (joint_chain.h): a still pose is
// still only when the joints were too, which their own stream (sensor_msgs/JointState, 100-1000 Hz)
// says. A view of a sensor behind joints keeps the median reading of each joint of its chain over its
// still run; a view whose joints moved during it, or that no reading covers, is dropped and counted.

#include <string>
#include <vector>

#include "vocal/calibration/calibration_types.h"
#include "vocal/calibration/joint_chain.h"

namespace vocal {

struct JointReading {
  double stamp = 0.0;     // seconds
  double position = 0.0;  // radians (metres), as the encoder reads it
};

struct JointStillnessOptions {
  // How far a joint's readings may spread over a still run: two encoder counts (a 12-bit encoder's are
  // 1.5 mrad) of flicker, no motion.
  double max_motion = 0.003;            // radians
  double max_prismatic_motion = 0.001;  // metres
  double margin = 0.05;  // seconds: a run no reading falls within takes the nearest this close to it
};

struct JointPositionCounts {
  int kept = 0;
  int moving = 0;      // views whose joints moved during their run
  int unread = 0;      // views no reading of a joint covers (joint states missing then, or never)
  std::string first;   // the first dropped view, in words: sensor, pose, joint and why
};

// Fills `joint_positions` of each view of a sensor behind joints (mounts.chains) from `readings` (per
// joint of mounts.joints, in time order) and drops those whose joints moved or were not read; others
// pass unchanged. `sensors` names them in `counts->first`.
std::vector<TargetObservation> attachJointPositions(std::vector<TargetObservation> views, const JointedMounts& mounts,
                                                    const std::vector<std::vector<JointReading>>& readings,
                                                    const std::vector<SensorSpec>& sensors, const JointStillnessOptions& options,
                                                    JointPositionCounts* counts);

}  // namespace vocal
