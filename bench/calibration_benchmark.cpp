// Google Benchmark of MSG-Cal's solve: a simulated rig of 3 RGB-D sensors and 2 lidars (5 sensors)
// observing 50 target poses with 1 mm range noise; plane fits, pairwise initialisation, the Ceres
// graph and the covariance all count.
//   devel/lib/vocal/calibration_benchmark

#include <benchmark/benchmark.h>

#include "vocal/calibration/graph_calibration.h"
#include "vocal/calibration/rig_simulator.h"

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
}  // namespace

BENCHMARK(BM_CalibrateRig)->Arg(50)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_MAIN();
