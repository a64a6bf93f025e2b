#pragma once
// A hand-eye rig's tool pose from a recording's /tf and /tf_static, as robot_state_publisher or an arm's
// driver publishes it: every transform loaded into one tf2 buffer, then the tool looked up in the
// reference frame at each instant a /tf message was stamped (the arm's own rate).

#include <string>

#include "vocal/calibration/calibration_session.h"

namespace vocal {

struct BagToolPoses {
  std::size_t samples = 0;       // tool poses given to the session
  std::size_t failed_lookups = 0;
  std::string last_failure;      // tf's words for the last lookup that failed
};

// Feeds session->addToolPose. Throws InputError naming the bag when it holds no /tf, or when the tool
// could never be looked up (tf's reason, e.g. the two frames not connected).
BagToolPoses readToolPosesFromBag(const std::string& bag_path, const std::string& reference_frame, const std::string& tool_frame,
                                  CalibrationSession* session);

}  // namespace vocal
