// still_poses_to_bag FOLDER OUT.bag: a folder of per-pose camera images and lidar scans as a recorded
// calibration session (each pose a still period), for calibrate_rig.

#include <cstdio>

#include "vocal/tools/command_line.h"
#include "vocal/tools/still_pose_bag.h"

namespace {
const char kUsage[] =
    "usage: still_poses_to_bag FOLDER OUT.bag [options]\n"
    "  FOLDER               images/NAME.jpg|png and clouds/NAME.pcd per pose (paired by NAME), camera_info.yaml;\n"
    "                       a stereo pair's second camera from images_right/NAME and camera_info_right.yaml\n"
    "  --still S            each pose held still S seconds (default 0.6), then ...\n"
    "  --moving S           ... S seconds with no message (default 1.4)\n"
    "  --camera-rate HZ     images + camera_info per second while still (default 10)\n"
    "  --lidar-rate HZ      clouds per second while still (default 10)\n"
    "  --first N            skip the first N poses (in NAME order)\n"
    "  --poses N            take N poses (default all)\n"
    "  --image-topic T      default /camera/image_raw (mono8); camera_info on --camera-info-topic\n"
    "  --camera-info-topic T   default /camera/camera_info\n"
    "  --cloud-topic T      default /velodyne_points (the PCD's fields as they are: x y z intensity ring ...)\n"
    "  --camera-frame F     default camera_optical\n"
    "  --lidar-frame F      default velodyne\n"
    "  --right-image-topic T   the second camera's, default /camera_right/image_raw (camera_info beside it:\n"
    "                       /camera_right/camera_info; --right-camera-info-topic T)\n"
    "  --right-camera-frame F  default camera_right_optical\n";

int run(const vocal::CommandLine& args) {
  vocal::StillPoseBagOptions options;
  options.still_seconds = args.number("still", options.still_seconds);
  options.moving_seconds = args.number("moving", options.moving_seconds);
  options.camera_rate = args.number("camera-rate", options.camera_rate);
  options.lidar_rate = args.number("lidar-rate", options.lidar_rate);
  options.first_pose = args.integer("first", options.first_pose);
  options.pose_count = args.integer("poses", options.pose_count);
  options.image_topic = args.text("image-topic", options.image_topic);
  options.camera_info_topic = args.text("camera-info-topic", options.camera_info_topic);
  options.cloud_topic = args.text("cloud-topic", options.cloud_topic);
  options.camera_frame = args.text("camera-frame", options.camera_frame);
  options.lidar_frame = args.text("lidar-frame", options.lidar_frame);
  options.right_image_topic = args.text("right-image-topic", options.right_image_topic);
  options.right_camera_info_topic = args.text("right-camera-info-topic", options.right_camera_info_topic);
  options.right_camera_frame = args.text("right-camera-frame", options.right_camera_frame);
  const vocal::StillPoseBagSummary summary = vocal::writeStillPoseBag(args.positional()[0], args.positional()[1], options);
  const std::string right =
      summary.right_images > 0 ? ", " + std::to_string(summary.right_images) + " images on " + options.right_image_topic : "";
  std::printf("wrote %zu poses (%s ... %s): %zu images on %s%s, %zu clouds on %s, to %s\n", summary.poses.size(),
              summary.poses.front().c_str(), summary.poses.back().c_str(), summary.images, options.image_topic.c_str(), right.c_str(),
              summary.clouds, options.cloud_topic.c_str(), args.positional()[1].c_str());
  return 0;
}
}  // namespace

int main(int argc, char** argv) {
  return vocal::runTool("still_poses_to_bag", kUsage, run, argc, argv,
                        {"still", "moving", "camera-rate", "lidar-rate", "first", "poses", "image-topic", "camera-info-topic",
                         "cloud-topic", "camera-frame", "lidar-frame", "right-image-topic", "right-camera-info-topic", "right-camera-frame"},
                        {}, 2);
}
