// Google Benchmark of MSG-Cal: the solve (a simulated rig of 3 RGB-D sensors and 2 lidars observing
// 50 target poses with 1 mm range noise; plane fits, pairwise initialisation, the Ceres graph and the
// covariance all count), and per VLP-16 cloud of the furnished room with a person holding the board
// (2 cm noise, +-2 cm ring offsets, mixed pixels): the target search, and adding its room planes to
// the ring offsets' estimate.
//   devel/lib/vocal/calibration_benchmark

#include <benchmark/benchmark.h>

#include <random>

#include "vocal/calibration/extraction/lidar_ring_offsets.h"
#include "vocal/calibration/extraction/target_extraction.h"
#include "vocal/calibration/solver/graph_calibration.h"
#include "vocal/simulation/rig_simulator.h"
#include "vocal/simulation/simulated_sensor_data.h"

namespace {
void BM_CalibrateRig(benchmark::State& state) {
  vocal::RigSimulationOptions options;
  options.target_poses = static_cast<int>(state.range(0));
  options.range_noise = 0.001;
  const vocal::SimulatedRig rig = vocal::simulateRig(vocal::exampleRig(3, 2), options);
  std::vector<vocal::SensorSpec> sensors;
  for (const auto& s : rig.sensors) sensors.push_back(s.spec);
  vocal::CalibrationOptions calibration;
  calibration.reference_pose = rig.sensors[0].reference_from_sensor;
  std::size_t points = 0;
  for (const auto& o : rig.observations) points += o.points.size();
  for (auto _ : state) benchmark::DoNotOptimize(vocal::calibrateRig(sensors, rig.observations, calibration));
  state.counters["sensors"] = static_cast<double>(rig.sensors.size());
  state.counters["observations"] = static_cast<double>(rig.observations.size());
  state.counters["points"] = static_cast<double>(points);
}

std::vector<Eigen::Vector3d> furnishedRoomLidarCloud() {
  static const vocal::SimulatedSensor lidar = vocal::exampleRig(0, 1, 0, 0)[0];
  static const vocal::TargetDescription target;
  std::mt19937 rng(3);
  vocal::SimulatedRoomView view = vocal::boardHeldInFurnishedRoom(lidar, target);
  view.range_noise = 0.02;
  std::uniform_real_distribution<double> offset(-0.02, 0.02);
  for (int ring = 0; ring < 16; ++ring) view.ring_bias.push_back(offset(rng));
  return vocal::simulateLidarCloud(view, &rng);
}

void BM_FindTargetInLidarCloud(benchmark::State& state) {
  const std::vector<Eigen::Vector3d> cloud = furnishedRoomLidarCloud();
  const vocal::ScanSpacing spacing = vocal::estimateScanSpacing(cloud);
  const vocal::TargetDescription target;
  for (auto _ : state) benchmark::DoNotOptimize(vocal::findTargetInCloud(cloud, target.width, target.height, spacing));
  state.counters["returns"] = static_cast<double>(cloud.size());
}

void BM_RingOffsetsAddPlanes(benchmark::State& state) {
  const std::vector<Eigen::Vector3d> cloud = furnishedRoomLidarCloud();
  const vocal::TargetDescription target;
  const vocal::ScanSpacing spacing = vocal::estimateScanSpacing(cloud);
  const vocal::TargetSearch search = vocal::findTargetInCloud(cloud, target.width, target.height, spacing);
  vocal::RingOffsetEstimator estimator(spacing.rings);
  std::size_t returns = 0;
  for (const auto& plane : search.room_points) returns += plane.size();
  for (auto _ : state) estimator.addPlanes(search.room_points);
  state.counters["planes"] = static_cast<double>(search.room_points.size());
  state.counters["returns"] = static_cast<double>(returns);
}
}  // namespace

BENCHMARK(BM_CalibrateRig)->Arg(50)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_FindTargetInLidarCloud)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_RingOffsetsAddPlanes)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_MAIN();
