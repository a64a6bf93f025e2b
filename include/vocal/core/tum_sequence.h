#pragma once
// A folder in the TUM RGB-D benchmark layout: rgb.txt and depth.txt list `timestamp filename`,
// frames are associated by nearest stamp (TUM rule), groundtruth.txt (optional) holds the camera
// trajectory, accelerometer.txt (optional) the Kinect's accelerometer, camera.yaml (optional, written by
// vocal's generator) the intrinsics.

#include <string>
#include <vector>

#include "vocal/core/gravity.h"
#include "vocal/core/lens_distortion.h"
#include "vocal/core/pinhole_camera.h"
#include "vocal/core/rgbd_frame.h"
#include "vocal/core/tum_trajectory.h"

namespace vocal {

struct TumListEntry {
  double stamp = 0.0;
  std::string path;  // absolute or relative to the working directory, ready to open
  int line_number = 0;
};

// Reads rgb.txt or depth.txt. Throws InputError naming the file and line for a malformed line,
// a stamp that does not increase, or a listed image that does not exist.
std::vector<TumListEntry> readTumImageList(const std::string& list_path, const std::string& folder);

struct TumFrameEntry {
  TumListEntry rgb;
  TumListEntry depth;
};

struct TumSequenceOptions {
  double max_time_difference = 0.02;  // seconds, the benchmark's association tolerance
};

class TumSequence {
 public:
  // Throws InputError when a list is missing or malformed, an image is missing, or no rgb/depth pair
  // is within max_time_difference (an empty sequence is an error, not zero frames).
  static TumSequence open(const std::string& folder, const TumSequenceOptions& options = {});

  const std::string& folder() const { return folder_; }
  std::size_t size() const { return frames_.size(); }
  const TumFrameEntry& entry(std::size_t index) const { return frames_.at(index); }
  const std::vector<TumFrameEntry>& entries() const { return frames_; }

  // Loads colour and depth (metres) of one associated pair; stamped with the rgb stamp. Throws
  // InputError naming the file for unreadable images or sizes that disagree with the camera.
  RgbdFrame loadFrame(std::size_t index) const;

  const PinholeCamera& camera() const { return camera_; }
  // The lens distortion the benchmark publishes for the folder's camera (none for camera.yaml, whose
  // intrinsics alone are read, and for other folders).
  const LensDistortion& lens() const { return lens_; }
  // Where the intrinsics came from (camera.yaml, or which benchmark default).
  const std::string& cameraSource() const { return camera_source_; }

  bool hasGroundTruth() const { return !ground_truth_.empty(); }
  const Trajectory& groundTruth() const { return ground_truth_; }
  // accelerometer.txt, in the Kinect's accelerometer frame (opticalFromKinectAccelerometer); empty without one.
  const std::vector<AccelerometerSample>& accelerometer() const { return accelerometer_; }

 private:
  std::string folder_;
  std::vector<TumFrameEntry> frames_;
  PinholeCamera camera_;
  LensDistortion lens_;
  std::string camera_source_;
  Trajectory ground_truth_;
  std::vector<AccelerometerSample> accelerometer_;
};

// The benchmark's published intrinsics for freiburg1/2/3 folders (recognised by name), else the ROS
// default; `source` says which was chosen; `lens` gets the published distortion (freiburg3's images
// are already undistorted).
PinholeCamera tumDefaultCamera(const std::string& folder, std::string* source, LensDistortion* lens = nullptr);

}  // namespace vocal
