#pragma once
// A camera path in the blank_wall scene that leaves structure for a blank wall and comes back: where
// vision alone stops and only an IMU carries the rotation (the method's "blank wall with no features").

#include <utility>

#include "vocal/core/tum_trajectory.h"

namespace vocal {

struct BlankWallVisitOptions {
  double frame_rate = 30.0;      // Hz
  // Looking into the room before the wall (what a gyro's bias is learned over: its error, times the
  // wall's span, is the rotation's drift there) and after it.
  double room_before_seconds = 4.0;
  double room_after_seconds = 2.0;
  double turn_seconds = 1.0;     // each 90 deg turn between the room and the wall (peak 2.4 rad/s)
  double wall_seconds = 10.0;    // facing the blank panel, turning (+-0.2 rad) and moving (+-15 cm)
  double start_stamp = 1.0e9;    // seconds
};

// Poses of the optical frame in SyntheticScene::make(SceneVariant::kBlankWall)'s world (z up): from the
// path's centre facing the room (+x, tilted 0.15 rad down), a turn to the panel (+y), the dwell, a turn
// back, the room again; small hand-held motion throughout. Throws InputError for a non-positive rate or
// a negative span.
Trajectory generateBlankWallVisit(const BlankWallVisitOptions& options);

// The stamps [first, last] of the frames that face the panel alone (the dwell, turns excluded).
std::pair<double, double> blankWallDwell(const BlankWallVisitOptions& options);

}  // namespace vocal
