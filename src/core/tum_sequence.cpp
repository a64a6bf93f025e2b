#include "vocal/core/tum_sequence.h"

#include <sys/stat.h>

#include <limits>

#include "vocal/core/camera_yaml.h"
#include "vocal/core/errors.h"
#include "vocal/core/image_io.h"
#include "vocal/core/stamp_association.h"
#include "vocal/core/tum_text_file.h"

namespace vocal {

namespace {
bool isRegularFile(const std::string& path) {
  struct stat info {};
  return ::stat(path.c_str(), &info) == 0 && S_ISREG(info.st_mode);
}

std::string joinPath(const std::string& folder, const std::string& name) {
  if (name.empty() || name.front() == '/' || folder.empty()) {
    return name;
  }
  return folder.back() == '/' ? folder + name : folder + "/" + name;
}

std::vector<double> stampsOf(const std::vector<TumListEntry>& entries) {
  std::vector<double> stamps;
  stamps.reserve(entries.size());
  for (const TumListEntry& e : entries) {
    stamps.push_back(e.stamp);
  }
  return stamps;
}
}  // namespace

std::vector<TumListEntry> readTumImageList(const std::string& list_path, const std::string& folder) {
  std::vector<TumListEntry> entries;
  double previous_stamp = -std::numeric_limits<double>::infinity();
  for (const TumTextLine& line : readTumTextLines(list_path)) {
    if (line.fields.size() != 2) {
      throw InputError(tumLineError(list_path, line.line_number,
                                    "expected 2 fields 'timestamp filename', found " +
                                        std::to_string(line.fields.size())));
    }
    const double stamp = parseTumNumber(list_path, line, 0, "timestamp");
    requireIncreasingStamp(list_path, line, previous_stamp, stamp);
    previous_stamp = stamp;
    const std::string path = joinPath(folder, line.fields[1]);
    if (!isRegularFile(path)) {
      throw InputError(tumLineError(list_path, line.line_number, "image '" + path + "' does not exist"));
    }
    entries.push_back({stamp, path, line.line_number});
  }
  return entries;
}

PinholeCamera tumDefaultCamera(const std::string& folder, std::string* source, LensDistortion* lens) {
  PinholeCamera camera;
  struct Published {
    const char* name;
    double fx, fy, cx, cy;
    std::vector<double> d;  // plumb_bob k1 k2 p1 p2 k3
  };
  // From the benchmark's calibration page ("Intrinsic Camera Calibration of the Kinect").
  static const Published kPublished[] = {
      {"freiburg1", 517.3, 516.5, 318.6, 255.3, {0.2624, -0.9531, -0.0054, 0.0026, 1.1633}},
      {"freiburg2", 520.9, 521.0, 325.1, 249.7, {0.2312, -0.7849, -0.0033, -0.0001, 0.9172}},
      {"freiburg3", 535.4, 539.2, 320.1, 247.6, {0.0, 0.0, 0.0, 0.0, 0.0}}};
  if (lens) *lens = LensDistortion();
  for (const Published& p : kPublished) {
    if (folder.find(p.name) != std::string::npos) {
      camera.fx = p.fx;
      camera.fy = p.fy;
      camera.cx = p.cx;
      camera.cy = p.cy;
      if (lens) *lens = LensDistortion::fromCameraInfo("plumb_bob", p.d, "TUM published distortion");
      *source = std::string("TUM ") + p.name + " intrinsics and distortion (folder name)";
      return camera;
    }
  }
  *source = "ROS default intrinsics fx=fy=525 cx=319.5 cy=239.5 (no camera.yaml, folder name not freiburg1/2/3)";
  return camera;
}

TumSequence TumSequence::open(const std::string& folder, const TumSequenceOptions& options) {
  TumSequence sequence;
  sequence.folder_ = folder;
  const std::vector<TumListEntry> rgb = readTumImageList(joinPath(folder, "rgb.txt"), folder);
  const std::vector<TumListEntry> depth = readTumImageList(joinPath(folder, "depth.txt"), folder);
  for (const StampMatch& m : associateStamps(stampsOf(rgb), stampsOf(depth), options.max_time_difference)) {
    sequence.frames_.push_back({rgb[m.first], depth[m.second]});
  }
  if (sequence.frames_.empty()) {
    throw InputError(folder + ": empty sequence: rgb.txt lists " + std::to_string(rgb.size()) +
                     " images and depth.txt " + std::to_string(depth.size()) + ", and no pair is within " +
                     std::to_string(options.max_time_difference) + " s");
  }
  const std::string camera_path = joinPath(folder, "camera.yaml");
  if (isRegularFile(camera_path)) {
    sequence.camera_ = readCameraYaml(camera_path);
    sequence.camera_source_ = camera_path;
  } else {
    sequence.camera_ = tumDefaultCamera(folder, &sequence.camera_source_, &sequence.lens_);
  }
  const std::string ground_truth_path = joinPath(folder, "groundtruth.txt");
  if (isRegularFile(ground_truth_path)) {
    sequence.ground_truth_ = readTumTrajectory(ground_truth_path);
  }
  const std::string accelerometer_path = joinPath(folder, "accelerometer.txt");
  if (isRegularFile(accelerometer_path)) sequence.accelerometer_ = readAccelerometerFile(accelerometer_path);
  return sequence;
}

RgbdFrame TumSequence::loadFrame(std::size_t index) const {
  const TumFrameEntry& e = entry(index);
  RgbdFrame frame;
  frame.stamp = e.rgb.stamp;
  frame.color = readColorPng(e.rgb.path);
  frame.depth = readDepthPng(e.depth.path, camera_.depth_scale);
  frame.validate(e.rgb.path + " + " + e.depth.path);
  if (!frame.color.sameSize(camera_.width, camera_.height)) {
    throw InputError(e.rgb.path + ": image is " + std::to_string(frame.color.width()) + "x" +
                     std::to_string(frame.color.height()) + " but the camera (" + camera_source_ + ") is " +
                     std::to_string(camera_.width) + "x" + std::to_string(camera_.height));
  }
  return frame;
}

}  // namespace vocal
