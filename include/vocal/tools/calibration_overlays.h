#pragma once
// calibrate_rig --overlays: per still pose and camera, the camera's image from the recording with every
// other sensor's board points drawn where the calibration puts them (calibration_overlay.h), written as
// PNGs, and how well they land on the board the camera saw.

#include <string>
#include <vector>

#include "vocal/calibration/output/calibration_overlay.h"
#include "vocal/calibration/rig_description.h"
#include "vocal/calibration/solver/graph_calibration.h"

namespace vocal {

struct OverlayPoseAgreement {
  int target_pose = 0;
  int camera = 0;  // the sensor whose image it is
  int sensor = 0;  // the sensor whose points are drawn
  bool rejected = false;  // its observation was rejected by the consensus filter
  OverlayAgreement agreement;
};

struct OverlayReport {
  std::vector<std::string> written;            // PNG paths
  std::vector<OverlayPoseAgreement> agreement;  // where the camera found the board again
  std::vector<std::string> problems;            // per overlay not drawn (no image, no camera_info)
  std::string contact_sheet;                    // every overlay's thumbnail in one PNG (empty: none drawn)
};

// One PNG per still pose and camera that saw it, DIR/overlay_pose<NN>_<camera>.png: the image nearest the
// middle of the camera's still run, read again from the bag; and DIR/overlays_contact_sheet.png, all of
// them as thumbnails, a pose's cameras side by side.
OverlayReport writeCalibrationOverlays(const std::string& bag_path, const RigDescription& rig,
                                       const std::vector<TargetObservation>& associated,
                                       const CalibrationResult& result, const std::string& dir);

}  // namespace vocal
