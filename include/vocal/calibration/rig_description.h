#pragma once
// The rig description YAML of the design: the contract between a user, the calibration tool and the
// MsgCalibration nodelet. Which sensors, of which type, on which topics, the target, and the pose of
// the reference sensor (optional initial guesses for the others).
//
//   reference_frame: base_link
//   target: {type: checkerboard, rows: 6, cols: 8, square_size: 0.06, width: 0.9, height: 0.7}
//   sensors:
//     - {name: kinect, type: rgbd, frame_id: camera_rgb_optical_frame, depth_topic: ...,
//        camera_info_topic: ..., pose: [x, y, z, qx, qy, qz, qw]}
//     - {name: lidar, type: lidar3d, frame_id: velodyne, cloud_topic: /velodyne_points,
//        crop_box: [0, -2, -1, 4, 2, 1]}   # optional, range sensors: search only inside (sensor frame)
//     - {name: scan, type: laser2d, frame_id: laser, scan_topic: /scan}
//     - {name: cam2, type: camera, frame_id: cam2_optical, image_topic: ..., camera_info_topic: ...}

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "vocal/calibration/calibration_types.h"
#include "vocal/calibration/extraction/pattern_observation.h"
#include "vocal/calibration/extraction/target_extraction.h"

namespace vocal {

struct TargetDescription {
  TargetPattern pattern;  // rows / cols count inner corners
  double width = 0.9;     // metres: the whole board, what range sensors see
  double height = 0.7;
};

struct RigSensorDescription {
  SensorSpec spec;
  std::string image_topic, camera_info_topic, depth_topic, cloud_topic, scan_topic;
  std::optional<Eigen::Isometry3d> pose;  // in reference_frame
  std::optional<CropBox> crop_box;        // range sensors: where the target is searched
};

struct RigDescription {
  std::string reference_frame = "base_link";
  TargetDescription target;
  std::vector<RigSensorDescription> sensors;
  int reference_sensor = 0;  // the first sensor with a pose

  std::vector<SensorSpec> specs() const;
};

// Throws InputError starting with `where` for a pattern under 2 x 2 inner corners, a square size or board
// side that is not positive, or a pattern whose squares do not fit on the board (its columns run along
// the width).
void checkTargetDescription(const TargetDescription& target, const std::string& where);

// Throws InputError naming the file and the key: unknown or missing keys, a sensor type without the
// topics it needs (camera: image + camera_info; rgbd: depth + camera_info; lidar3d: cloud; laser2d:
// scan), a malformed crop_box or one on a camera, duplicate names, no sensor with a pose, a reference that is a 2D laser, a bad target.
RigDescription readRigDescription(const std::string& path);

// Writes what readRigDescription reads (every sensor with a pose writes it). Throws InputError naming
// the file when it cannot be written.
void writeRigDescription(const std::string& path, const RigDescription& rig);

}  // namespace vocal
