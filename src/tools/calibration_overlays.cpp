#include "vocal/tools/calibration_overlays.h"

#include <algorithm>
#include <cstdio>
#include <map>
#include <optional>

#include "vocal/calibration/extraction/pattern_observation.h"
#include "vocal/core/errors.h"
#include "vocal/core/image_io.h"
#include "vocal/tools/calibration_bag.h"

namespace vocal {

namespace {
constexpr std::size_t kMaxDrawnPoints = 4000;  // per layer: a depth sensor's pooled run has 10^5

Rgb8 layerColour(int sensor) {
  static const Rgb8 palette[] = {{255, 60, 60}, {255, 220, 0}, {0, 200, 255}, {255, 0, 255}, {255, 140, 0}, {120, 120, 255}};
  return palette[sensor % (sizeof(palette) / sizeof(palette[0]))];
}

constexpr int kThumbnailWidth = 320;  // pixels: six across a 1920-pixel screen

// What a thumbnail still says when its overlay's legend is too small to read: the least share of a
// sensor's points on the board the camera found (none when it found no board or drew no sensor).
std::string thumbnailLabel(int pose, const std::string& camera, const std::optional<double>& worst_on_board) {
  char text[96];
  if (!worst_on_board) {
    std::snprintf(text, sizeof(text), "pose %d, %s", pose, camera.c_str());
  } else {
    std::snprintf(text, sizeof(text), "pose %d, %s: %.0f%% or more on board", pose, camera.c_str(), 100 * *worst_on_board);
  }
  return text;
}

bool rejected(const CalibrationResult& result, int sensor, int pose) {
  for (const ObservationResidual& o : result.observations)
    if (o.sensor == sensor && o.target_pose == pose) return o.rejected;
  return false;
}
}  // namespace

OverlayReport writeCalibrationOverlays(const std::string& bag_path, const RigDescription& rig,
                                       const std::vector<TargetObservation>& associated,
                                       const CalibrationResult& result, const std::string& dir) {
  std::vector<const TargetObservation*> views;  // the cameras' observations
  std::vector<CameraImageRequest> requests;
  for (const TargetObservation& o : associated) {
    if (rig.sensors.at(o.sensor).spec.type != SensorType::kCamera) continue;
    views.push_back(&o);
    requests.push_back({o.sensor, 0.5 * (o.first_stamp + o.last_stamp)});
  }
  const std::vector<CameraImage> images = readCameraImagesNear(bag_path, rig, requests);

  OverlayReport report;
  std::map<std::pair<int, int>, ColorImage> thumbnails;  // by (pose, camera); full-size overlays are megabytes each
  const double width = rig.target.width, height = rig.target.height;
  for (std::size_t v = 0; v < views.size(); ++v) {
    const TargetObservation& view = *views[v];
    const std::string& camera_name = rig.sensors[view.sensor].spec.name;
    const CameraImage& image = images[v];
    if (!image.found) {
      report.problems.push_back("pose " + std::to_string(view.target_pose) + ", " + camera_name +
                                ": no image or no usable camera_info in the bag");
      continue;
    }
    OverlayBoard board;
    try {  // the board as the camera sees it in this one image, independent of the calibration
      board.corners = detectPattern(image.image, rig.target.pattern, camera_name.c_str());
      board.camera_from_board =
          observePattern(board.corners, rig.target.pattern, image.camera, camera_name.c_str(), image.lens).plane.sensor_from_pattern;
      board.width = width, board.height = height;
    } catch (const InputError&) {
      board.corners.clear();  // drawn without the board; no agreement counted
    }
    // Where each sensor was at this still pose (behind joints or on an arm's tool: its mount frame there).
    const Eigen::Isometry3d camera_from_reference = result.rigFromSensorAt(view).inverse();
    std::vector<OverlayLayer> layers;
    std::optional<double> worst_on_board;  // of the layers, on the board the camera found
    for (const TargetObservation& o : associated) {
      if (o.target_pose != view.target_pose || o.sensor == view.sensor) continue;
      const Eigen::Isometry3d camera_from_sensor = camera_from_reference * result.rigFromSensorAt(o);
      OverlayLayer layer{rig.sensors[o.sensor].spec.name, layerColour(o.sensor), {}};
      std::vector<Eigen::Vector3d> points;
      points.reserve(o.points.size());
      for (const Eigen::Vector3d& p : o.points) points.push_back(camera_from_sensor * p);
      const bool was_rejected = rejected(result, o.sensor, o.target_pose);
      if (board.width > 0.0) {
        const OverlayAgreement agreement = overlayAgreement(points, board.camera_from_board, width, height);
        report.agreement.push_back({view.target_pose, view.sensor, o.sensor, was_rejected, agreement});
        worst_on_board = std::min(worst_on_board.value_or(1.0), agreement.on_board);
        char text[96];
        std::snprintf(text, sizeof(text), ": %.0f%% on the board, %.1f mm off its plane", 100 * agreement.on_board,
                      1000 * agreement.plane_rms);
        layer.label += text;
      }
      if (was_rejected) layer.label += " (rejected)";
      const std::size_t stride = 1 + points.size() / kMaxDrawnPoints;
      for (std::size_t i = 0; i < points.size(); i += stride) layer.points.push_back(points[i]);
      layers.push_back(std::move(layer));
    }
    char title[128];
    std::snprintf(title, sizeof(title), "pose %d, %s at %.2f s%s", view.target_pose, camera_name.c_str(), image.stamp,
                  board.width > 0.0 ? "" : " (board not found in this image)");
    char name[64];
    std::snprintf(name, sizeof(name), "/overlay_pose%02d_", view.target_pose);
    const std::string path = dir + name + camera_name + ".png";
    const ColorImage overlay = drawCalibrationOverlay(image.image, image.camera, image.lens, board, layers, title);
    writeColorPng(path, overlay);
    report.written.push_back(path);
    thumbnails[{view.target_pose, view.sensor}] =
        labelledThumbnail(overlay, kThumbnailWidth, thumbnailLabel(view.target_pose, camera_name, worst_on_board));
  }
  if (!thumbnails.empty()) {
    // A column per camera, whole poses per row (about six thumbnails across), a gap where a camera
    // missed a pose.
    std::vector<int> cameras;
    int poses = 0;
    for (const TargetObservation* view : views) {
      if (std::find(cameras.begin(), cameras.end(), view->sensor) == cameras.end()) cameras.push_back(view->sensor);
      poses = std::max(poses, view->target_pose + 1);
    }
    std::sort(cameras.begin(), cameras.end());
    std::vector<ColorImage> cells(static_cast<std::size_t>(poses) * cameras.size());
    for (auto& [key, thumbnail] : thumbnails) {
      const auto column = std::find(cameras.begin(), cameras.end(), key.second) - cameras.begin();
      cells[key.first * cameras.size() + column] = std::move(thumbnail);
    }
    const int per_pose = static_cast<int>(cameras.size());
    report.contact_sheet = dir + "/overlays_contact_sheet.png";
    writeColorPng(report.contact_sheet, contactSheet(cells, per_pose * std::max(1, 6 / per_pose)));
  }
  return report;
}

}  // namespace vocal
