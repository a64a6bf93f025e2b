// simulate_imu TRAJECTORY OUT_DIR [options]: an IMU along a camera path (TUM format: a TUM folder's
// groundtruth.txt, or a synthetic sequence's), written as OUT_DIR/imu.txt and OUT_DIR/imu_extrinsics.yaml,
// what tum_odometry --imu / --imu-extrinsics read.

#include <cmath>
#include <cstdio>

#include "vocal/core/folders.h"
#include "vocal/core/imu_samples.h"
#include "vocal/core/tum_trajectory.h"
#include "vocal/simulation/simulated_imu.h"
#include "vocal/tools/command_line.h"

namespace {
const char kUsage[] =
    "usage: simulate_imu TRAJECTORY OUT_DIR [options]   (the camera's optical frame in the world, TUM format, world z up)\n"
    "  --rate HZ            samples per second (default 200)\n"
    "  --seed N             the noise's and the bias's draw (default 1)\n"
    "  --bias-deg-s B       each gyro axis's constant bias drawn within +-B deg/s (default 0.5)\n"
    "  --time-offset S      IMU stamp = camera stamp + S (default 0), also written into imu_extrinsics.yaml\n"
    "The IMU sits as a RealSense D435i's (x forward, y left, z up, 15 mm beside the optical centre), with its\n"
    "consumer MEMS noise (gyro 2.4e-4 rad/s/sqrt(Hz), bias walk 2e-5; accelerometer 2e-3 m/s^2/sqrt(Hz), walk 3e-4).\n";

int run(const vocal::CommandLine& args) {
  const vocal::Trajectory path = vocal::readTumTrajectory(args.positional()[0]);
  const std::string out = args.positional()[1];
  vocal::makeFolders(out);
  vocal::SimulatedImuOptions options;
  options.extrinsics = vocal::simulatedImuExtrinsics();
  options.rate = args.number("rate", options.rate);
  options.seed = static_cast<std::uint32_t>(args.integer("seed", 1));
  options.bias_limit = args.number("bias-deg-s", 0.5) * M_PI / 180.0;
  options.extrinsics.time_offset = args.number("time-offset", 0.0);
  Eigen::Vector3d bias;
  const std::vector<vocal::ImuSample> samples = vocal::simulateImu(path, options, &bias);
  vocal::writeImuFile(out + "/imu.txt", samples);
  vocal::writeImuExtrinsics(out + "/imu_extrinsics.yaml", options.extrinsics);
  bias *= 180.0 / M_PI;
  std::printf("wrote %zu samples (%.0f Hz, gyro bias %.3f %.3f %.3f deg/s) to %s/imu.txt and %s/imu_extrinsics.yaml\n", samples.size(),
              options.rate, bias.x(), bias.y(), bias.z(), out.c_str(), out.c_str());
  return 0;
}
}  // namespace

int main(int argc, char** argv) {
  return vocal::runTool("simulate_imu", kUsage, run, argc, argv, {"rate", "seed", "bias-deg-s", "time-offset"}, {}, 2);
}
