#pragma once
// A folder of still poses (one camera image and one lidar scan per pose, as calibration samples are
// often shared: cam_lidar_calibration, Autoware's and others' sample sets) written as a robot records a
// session: each pose a still period of camera images + camera_info and clouds at their rates, the
// poses apart in time, so calibrate_rig and the nodelet read it as they read a live recording.
//
// Folder layout: images/NAME.{jpg,png} and clouds/NAME.pcd paired by NAME (sorted), camera_info.yaml
// (the ROS camera_info YAML, or the flat `width height K D distortion_model` layout; `fisheye` is read
// as ROS's `equidistant`). A second camera of a stereo pair, when the folder has it: images_right/NAME
// for every pose and camera_info_right.yaml, written on the right camera's topics at the same stamps.

#include <string>
#include <vector>

namespace vocal {

struct StillPoseBagOptions {
  std::string image_topic = "/camera/image_raw";
  std::string camera_info_topic = "/camera/camera_info";
  std::string cloud_topic = "/velodyne_points";
  std::string camera_frame = "camera_optical";
  std::string lidar_frame = "velodyne";
  // The second camera's (images_right/, when there).
  std::string right_image_topic = "/camera_right/image_raw";
  std::string right_camera_info_topic = "/camera_right/camera_info";
  std::string right_camera_frame = "camera_right_optical";
  double still_seconds = 0.6;   // each pose held still this long ...
  double moving_seconds = 1.4;  // ... then nothing is published for this long (the board carried on)
  double camera_rate = 10.0;    // Hz
  double lidar_rate = 10.0;     // Hz
  int first_pose = 0;           // the poses taken, in NAME order
  int pose_count = -1;          // < 0: all from first_pose on
};

struct StillPoseBagSummary {
  std::vector<std::string> poses;  // NAMEs written, in order
  std::size_t images = 0, clouds = 0;
  std::size_t right_images = 0;  // 0 when the folder has no images_right/
};

// Throws InputError naming the folder or file: no images/ or clouds/, an image without its cloud (or the
// reverse), a pose without its right image where images_right/ is there, no camera_info_right.yaml then, an unreadable image, PCD or camera_info, a camera_info that does not fit the images, no pose in
// the range asked for, or a bag that cannot be written.
StillPoseBagSummary writeStillPoseBag(const std::string& folder, const std::string& bag_path, const StillPoseBagOptions& options);

}  // namespace vocal
