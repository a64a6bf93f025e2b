#pragma once
// A calibration result as the files a ROS user applies: the result YAML of the design (per sensor:
// frame_id, parent, translation, rotation and their standard deviations), a URDF snippet of fixed
// joints, and a launch file of static transform publishers.

#include <optional>
#include <string>
#include <vector>

#include "vocal/calibration/calibration_types.h"
#include "vocal/calibration/graph_calibration.h"
#include "vocal/calibration/lidar_ring_offsets.h"
#include "vocal/calibration/pose_jackknife.h"

namespace vocal {

// Each throws InputError naming the file when it cannot be written. With `spread`, the YAML also gives
// each sensor's jackknife standard deviations over the still poses (translation_spread, rotation_spread);
// with `ring_offsets` (per sensor), each 3D lidar's range offset per ring its board returns were corrected by.
void writeCalibrationYaml(const std::string& path, const std::string& reference_frame,
                          const std::vector<SensorSpec>& sensors, const CalibrationResult& result,
                          const PoseJackknife* spread = nullptr,
                          const std::vector<std::optional<RingOffsets>>* ring_offsets = nullptr);
void writeUrdfSnippet(const std::string& path, const std::string& reference_frame, const std::vector<SensorSpec>& sensors,
                      const CalibrationResult& result);
void writeStaticTransformLaunch(const std::string& path, const std::string& reference_frame,
                                const std::vector<SensorSpec>& sensors, const CalibrationResult& result);

}  // namespace vocal
