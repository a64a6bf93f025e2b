// tum_to_bag TUM_FOLDER OUTPUT.bag: a TUM-layout folder as a bag in the benchmark's own bag layout, or
// as openni2_launch would have recorded it.

#include <cstdio>
#include <string>

#include "vocal/tools/command_line.h"
#include "vocal/tools/tum_bag_writer.h"

namespace {
const char kUsage[] =
    "usage: tum_to_bag TUM_FOLDER OUTPUT.bag [--layout tum|openni2] [--max-difference S] [--imu DIR] [--quiet]\n"
    "  tum (default): /camera/rgb/image_color (rgb8), /camera/depth/image (32FC1 m), /camera/rgb/camera_info,\n"
    "          /camera/depth/camera_info, /tf world -> kinect (ground truth), /tf_static\n"
    "  openni2: /camera/rgb/image_rect_color (bgr8), /camera/depth_registered/image_raw (16UC1 mm),\n"
    "          /camera/rgb/camera_info, /camera/depth_registered/camera_info, /tf_static (no ground truth)\n"
    "  camera_info carries the folder's camera (camera.yaml, else TUM's published intrinsics and lens\n"
    "  distortion by the folder's name): TUM's images are not undistorted.\n"
    "  --imu DIR: DIR/imu.txt and DIR/imu_extrinsics.yaml (simulate_imu) on /camera/imu (gyro and accelerometer, in\n"
    "          the IMU's frame, on tf from the colour optical frame), as a RealSense driver publishes its IMU\n";

int run(const vocal::CommandLine& args) {
  vocal::TumSequenceOptions options;
  options.max_time_difference = args.number("max-difference", options.max_time_difference);
  vocal::TumBagOptions bag_options;
  if (args.has("layout")) bag_options.layout = vocal::parseBagLayout(args.text("layout", ""));
  bag_options.imu_folder = args.text("imu", "");
  const vocal::TumSequence sequence = vocal::TumSequence::open(args.positional()[0], options);
  std::fprintf(stderr, "%zu associated frames, intrinsics from %s\n", sequence.size(), sequence.cameraSource().c_str());
  if (!sequence.hasGroundTruth() && bag_options.layout == vocal::BagLayout::kTum) {
    std::fprintf(stderr, "no groundtruth.txt: the bag will have no world -> kinect transforms\n");
  }
  if (sequence.accelerometer().empty() && bag_options.layout == vocal::BagLayout::kTum) {
    std::fprintf(stderr, "no accelerometer.txt: the bag will have no /imu, and the odometry on it cannot start level\n");
  }
  const bool quiet = args.has("quiet");
  const vocal::TumBagSummary summary =
      vocal::writeTumBag(sequence, args.positional()[1], bag_options, [quiet](std::size_t done, std::size_t total) {
        if (!quiet) std::fprintf(stderr, "\rwriting frame %zu/%zu", done, total);
      });
  if (!quiet) std::fprintf(stderr, "\n");
  const std::string imu = summary.imu_samples ? " (and " + std::to_string(summary.imu_samples) + " IMU samples on /camera/imu)" : "";
  std::printf("wrote %zu frames, %zu ground-truth poses and %zu accelerometer samples%s to %s\n", summary.frames,
              summary.ground_truth_poses, summary.accelerometer_samples, imu.c_str(), args.positional()[1].c_str());
  return 0;
}
}  // namespace

int main(int argc, char** argv) {
  return vocal::runTool("tum_to_bag", kUsage, run, argc, argv, {"layout", "max-difference", "imu"}, {"quiet"}, 2);
}
