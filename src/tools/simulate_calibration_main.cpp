// simulate_calibration [options]: MSG-Cal on simulated rigs with known extrinsics, over repeated trials
// and a range of target-pose counts (the seed's Figure 4.5 experiments): mean translation and rotation
// errors against ground truth, RMS graph error, global vs best pairwise, with vs without the filter,
// and the global solution's worst sensor over the trials.

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <cstdio>
#include <sstream>
#include <string>
#include <vector>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "vocal/calibration/output/calibration_output.h"
#include "vocal/calibration/solver/graph_calibration.h"
#include "vocal/core/errors.h"
#include "vocal/core/folders.h"
#include "vocal/core/se3.h"
#include "vocal/simulation/rig_simulator.h"
#include "vocal/tools/command_line.h"

namespace {
const char kUsage[] =
    "usage: simulate_calibration [options]\n"
    "  --rgbd N --lidar N --laser N --camera N\n"
    "                                 sensors of the rig (default 2 RGB-D, 2 lidars, 1 2D laser, 1 camera;\n"
    "                                 the first RGB-D sensor is the reference)\n"
    "  --pattern ROWSxCOLSxSQUARE     the cameras' checkerboard (default 6x8x0.06: inner corners, metres)\n"
    "  --pixel-noise PX               camera corner noise (default 0.5)\n"
    "  --poses LIST                   target pose counts to try, comma separated (default 5,10,20,30,50)\n"
    "  --trials K                     trials per setting (default 10)\n"
    "  --noise M                      range noise, metres (default 0.001)\n"
    "  --outliers F                   fraction of outlier observations (default 0)\n"
    "  --seed S                       first seed (default 1)\n"
    "  --turn RAD                     how far the target turns left / right (default: as far as it tilts, 0.6);\n"
    "                                 e.g. 0.03: tilted mainly up and down, normals of little spread\n"
    "  --edges                        hold the board's outline as well as its plane (range sensors' line ends,\n"
    "                                 the cameras' board outline from PnP)\n"
    "  --plot FILE.png                mean errors against the number of poses (log scale)\n"
    "  --output-dir DIR               the last trial's result as rig.yaml, rig.urdf, rig.launch\n";

struct Accumulator {
  double translation = 0.0, rotation = 0.0;
  double worst_translation = 0.0, worst_rotation = 0.0;
  int count = 0;
  void add(const Eigen::Isometry3d& estimate, const Eigen::Isometry3d& truth) {
    const Eigen::Isometry3d difference = truth.inverse() * estimate;
    const double moved = difference.translation().norm(), turned = vocal::rotationAngle(difference);
    translation += moved, rotation += turned;
    worst_translation = std::max(worst_translation, moved), worst_rotation = std::max(worst_rotation, turned);
    ++count;
  }
  double meanTranslation() const { return count ? translation / count : 0.0; }
  double meanRotation() const { return count ? rotation / count : 0.0; }
};

// The four estimates compared in every row and plotted as four series.
enum Series { kGlobalFiltered, kPairwiseFiltered, kGlobalUnfiltered, kPairwiseUnfiltered, kSeriesCount };

struct Row {
  int poses = 0;
  std::array<Accumulator, kSeriesCount> series;
  double rms = 0.0;
  int failures = 0;
  std::string first_failure;
  std::map<vocal::SensorType, Accumulator> by_type;  // global + filter
};

std::vector<int> parseList(const std::string& text) {
  std::vector<int> values;
  std::istringstream stream(text);
  for (std::string item; std::getline(stream, item, ',');) {
    try {
      values.push_back(std::stoi(item));
    } catch (const std::exception&) {
      throw vocal::InputError("option --poses: '" + item + "' is not an integer");
    }
  }
  if (values.empty()) throw vocal::InputError("option --poses: no value");
  return values;
}

void plot(const std::string& path, const std::vector<Row>& rows) {
  cv::Mat image(520, 1200, CV_8UC3, cv::Scalar(255, 255, 255));
  auto panel = [&](int x0, const char* title, bool translation) {
    const cv::Rect area(x0 + 70, 60, 480, 380);
    // Log scale: errors span from a fraction of a millimetre to metres when the filter is off.
    double low = 1e300, high = 1e-300;
    for (const Row& r : rows)
      for (const Accumulator& a : r.series) {
        const double v = std::max(translation ? a.meanTranslation() : a.meanRotation(), 1e-9);
        low = std::min(low, v), high = std::max(high, v);
      }
    const double decade_low = std::floor(std::log10(low)), decade_high = std::max(std::ceil(std::log10(high)), decade_low + 1);
    const int first = rows.front().poses, last = std::max(rows.back().poses, first + 1);
    auto map = [&](int poses, double value) {
      const double y = (std::log10(std::max(value, 1e-9)) - decade_low) / (decade_high - decade_low);
      return cv::Point(area.x + (poses - first) * area.width / (last - first),
                       area.y + area.height - static_cast<int>(y * area.height));
    };
    for (double decade = decade_low; decade <= decade_high; decade += 1.0) {
      const cv::Point at = map(first, std::pow(10.0, decade));
      cv::line(image, at, cv::Point(area.x + area.width, at.y), cv::Scalar(215, 215, 215));
      char label[16];
      std::snprintf(label, sizeof(label), "1e%d", static_cast<int>(decade));
      cv::putText(image, label, cv::Point(x0 + 20, at.y + 5), cv::FONT_HERSHEY_SIMPLEX, 0.45, cv::Scalar(0, 0, 0), 1,
                  cv::LINE_AA);
    }
    cv::rectangle(image, area, cv::Scalar(0, 0, 0));
    cv::putText(image, title, cv::Point(area.x, 40), cv::FONT_HERSHEY_SIMPLEX, 0.6, cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
    for (const Row& r : rows) {
      cv::putText(image, std::to_string(r.poses), cv::Point(map(r.poses, high).x - 8, area.y + area.height + 20),
                  cv::FONT_HERSHEY_SIMPLEX, 0.45,
                  cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
    }
    cv::putText(image, "target poses", cv::Point(area.x + 190, area.y + area.height + 45), cv::FONT_HERSHEY_SIMPLEX, 0.5,
                cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
    const std::vector<std::pair<const char*, cv::Scalar>> legend = {{"global + filter", cv::Scalar(200, 90, 20)},  // in Series order
                                                                    {"pairwise + filter", cv::Scalar(40, 160, 40)},
                                                                    {"global, no filter", cv::Scalar(60, 60, 220)},
                                                                    {"pairwise, no filter", cv::Scalar(120, 120, 120)}};
    for (std::size_t k = 0; k < legend.size(); ++k) {
      for (std::size_t i = 1; i < rows.size(); ++i) {
        const Accumulator& a = rows[i - 1].series[k];
        const Accumulator& b = rows[i].series[k];
        const double va = translation ? a.meanTranslation() : a.meanRotation();
        const double vb = translation ? b.meanTranslation() : b.meanRotation();
        cv::line(image, map(rows[i - 1].poses, va), map(rows[i].poses, vb), legend[k].second, 2, cv::LINE_AA);
      }
      cv::line(image, cv::Point(area.x + 250, area.y + 15 + 18 * k), cv::Point(area.x + 280, area.y + 15 + 18 * k),
               legend[k].second, 2);
      cv::putText(image, legend[k].first, cv::Point(area.x + 288, area.y + 20 + 18 * k), cv::FONT_HERSHEY_SIMPLEX, 0.45,
                  cv::Scalar(0, 0, 0), 1, cv::LINE_AA);
    }
  };
  panel(0, "mean translation error [m]", true);
  panel(600, "mean rotation error [rad]", false);
  if (!cv::imwrite(path, image)) throw vocal::InputError(path + ": cannot write plot");
}

int run(const vocal::CommandLine& args) {
  if (args.has("output-dir")) vocal::makeFolders(args.text("output-dir", ""));  // before the trials, not after
  const int rgbd = args.integer("rgbd", 2), lidar = args.integer("lidar", 2), laser = args.integer("laser", 1),
            cameras = args.integer("camera", 1);
  vocal::TargetPattern pattern;  // the design's example board
  if (args.has("pattern")) {
    const std::string text = args.text("pattern", "");
    char x1 = 0, x2 = 0;
    std::istringstream fields(text);
    if (!(fields >> pattern.rows >> x1 >> pattern.cols >> x2 >> pattern.square_size) || x1 != 'x' || x2 != 'x' ||
        pattern.rows < 2 || pattern.cols < 2 || !(pattern.square_size > 0.0)) {
      throw vocal::InputError("option --pattern: '" + text + "' is not ROWSxCOLSxSQUARE, e.g. 6x8x0.06");
    }
  }
  if (rgbd < 1) throw vocal::InputError("option --rgbd: the reference is an RGB-D sensor, at least 1 is needed");
  const std::vector<int> pose_counts = parseList(args.text("poses", "5,10,20,30,50"));
  const int trials = args.integer("trials", 10);
  const std::vector<vocal::SimulatedSensor> sensors = vocal::exampleRig(rgbd, lidar, laser, cameras);
  std::vector<vocal::SensorSpec> specs;
  for (const auto& s : sensors) specs.push_back(s.spec);

  std::vector<Row> rows;
  vocal::SimulatedRig last_rig;
  vocal::CalibrationResult last_result;
  for (int poses : pose_counts) {
    Row row;
    row.poses = poses;
    for (int trial = 0; trial < trials; ++trial) {
      vocal::RigSimulationOptions options;
      options.target_poses = poses;
      options.range_noise = args.number("noise", 0.001);
      options.outlier_fraction = args.number("outliers", 0.0);
      options.pixel_noise = args.number("pixel-noise", 0.5);
      options.pattern = pattern;
      options.turn_range = args.number("turn", -1.0);
      options.seed = static_cast<std::uint32_t>(args.integer("seed", 1) + 1000 * trial + poses);
      const vocal::SimulatedRig rig = vocal::simulateRig(sensors, options);
      vocal::CalibrationOptions calibration;
      calibration.reference_pose = rig.sensors[0].reference_from_sensor;
      calibration.board_edges.enabled = args.has("edges");
      calibration.board_edges.width = options.target_width;
      calibration.board_edges.height = options.target_height;
      try {
        const vocal::CalibrationResult filtered = vocal::calibrateRig(specs, rig.observations, calibration);
        if (!filtered.trusted) throw vocal::InputError("not trusted: " + filtered.failure);
        calibration.consensus_filter = false;
        const vocal::CalibrationResult unfiltered = vocal::calibrateRig(specs, rig.observations, calibration);
        for (std::size_t s = 1; s < sensors.size(); ++s) {
          const Eigen::Isometry3d& truth = rig.sensors[s].reference_from_sensor;
          row.series[kGlobalFiltered].add(filtered.sensors[s].reference_from_sensor, truth);
          row.by_type[rig.sensors[s].spec.type].add(filtered.sensors[s].reference_from_sensor, truth);
          row.series[kPairwiseFiltered].add(filtered.sensors[s].pairwise_estimate, truth);
          row.series[kGlobalUnfiltered].add(unfiltered.sensors[s].reference_from_sensor, truth);
          row.series[kPairwiseUnfiltered].add(unfiltered.sensors[s].pairwise_estimate, truth);
        }
        row.rms += filtered.rms;
        last_rig = rig;
        last_result = filtered;
      } catch (const vocal::InputError& e) {
        if (row.failures++ == 0) row.first_failure = e.what();
      }
    }
    const int solved = trials - row.failures;
    row.rms = solved ? row.rms / solved : 0.0;
    rows.push_back(row);
  }

  std::printf("rig: %d RGB-D (reference: rgbd0), %d lidar3d, %d laser2d, %d camera; %d trials; range noise %.4g m; "
              "pixel noise %.3g px; outliers %.0f%%; target turned up to %.3g rad; %s\n",
              rgbd, lidar, laser, cameras, trials, args.number("noise", 0.001), args.number("pixel-noise", 0.5),
              100 * args.number("outliers", 0.0), args.number("turn", 0.6), args.has("edges") ? "planes and edges" : "planes only");
  std::printf("mean over the non-reference sensors and trials: translation error m / rotation error rad\n");
  std::printf("%6s %24s %24s %24s %24s %24s %12s %8s\n", "poses", "global+filter", "pairwise+filter", "global,no filter",
              "pairwise,no filter", "worst global+filter", "rms_m", "failed");
  for (const Row& r : rows) {
    std::printf("%6d", r.poses);
    for (const Accumulator& a : r.series) std::printf(" %11.6f / %10.7f", a.meanTranslation(), a.meanRotation());
    const Accumulator& global = r.series[kGlobalFiltered];
    std::printf(" %11.6f / %10.7f %12.6f %8d\n", global.worst_translation, global.worst_rotation, r.rms, r.failures);
    if (r.failures) std::printf("       first failure: %s\n", r.first_failure.c_str());
    for (const auto& [type, errors] : r.by_type) {
      std::printf("       %-8s global + filter: mean %.2f mm / %.2f mrad, worst %.2f mm / %.2f mrad\n", vocal::sensorTypeName(type).c_str(),
                  1000 * errors.meanTranslation(), 1000 * errors.meanRotation(), 1000 * errors.worst_translation,
                  1000 * errors.worst_rotation);
    }
  }
  for (const vocal::ObservabilityWarning& w : last_result.warnings) std::printf("warning (last trial): %s\n", w.message.c_str());
  if (args.has("plot")) plot(args.text("plot", ""), rows);
  if (args.has("output-dir") && !last_result.sensors.empty()) {
    const std::string dir = args.text("output-dir", "");
    vocal::writeCalibrationYaml(dir + "/rig.yaml", "base_link", specs, last_result);
    vocal::writeUrdfSnippet(dir + "/rig.urdf", "base_link", specs, last_result);
    vocal::writeStaticTransformLaunch(dir + "/rig.launch", "base_link", specs, last_result);
  }
  return 0;
}
}  // namespace

int main(int argc, char** argv) {
  return vocal::runTool("simulate_calibration", kUsage, run, argc, argv,
                        {"rgbd", "lidar", "laser", "camera", "pattern", "pixel-noise", "poses", "trials", "noise", "outliers", "seed",
                         "plot", "output-dir", "turn"},
                        {"edges"}, 0);
}
