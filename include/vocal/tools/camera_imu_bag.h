#pragma once
// A waved camera-IMU session written as a rosbag (simulated) and read from one (calibrate_rig with an `imu` in the rig): every frame of
// the IMU's camera searched for the board (PnP pose and covariance per frame) and every IMU sample.

#include <cstddef>
#include <string>
#include <vector>

#include "vocal/calibration/rig_description.h"
#include "vocal/calibration/solver/camera_imu_calibration.h"
#include "vocal/core/imu_samples.h"
#include "vocal/core/lens_distortion.h"
#include "vocal/core/pinhole_camera.h"
#include "vocal/simulation/waved_camera_imu.h"

namespace vocal {

struct CameraImuRecording {
  std::vector<CameraImuView> views;  // by stamp, frames with the board found
  std::vector<ImuSample> imu;        // by stamp
  PinholeCamera camera;              // the camera's first usable camera_info
  LensDistortion lens;
  std::size_t images = 0;            // the camera's frames
  std::size_t imu_messages = 0;
  std::size_t dropped = 0;           // messages that could not be read, or IMU samples out of order
  std::vector<std::string> problems;  // the first few of them: topic, bag time, why
};

// Rig imu `imu`'s messages and its camera's frames, the board searched in `threads` frames at once (0: the
// cores). Throws InputError naming the bag for no camera_info, no frame or no IMU message on the rig's topics.
CameraImuRecording readCameraImuBag(const std::string& bag_path, const RigDescription& rig, int imu, int threads = 0);

// The rig of a simulated waved session: its camera `camera_name` (the reference, at `camera_in_rig` in
// base_link; images on /NAME/image_raw, or .../compressed, camera_info on /NAME/camera_info: the topics a
// still-pose session's camera of that name has) and its IMU (imu_link on /imu/data, no pose) with the
// session's noise figures; the board's size from the options' pattern (a 5 cm margin).
RigDescription simulatedCameraImuRig(const WavedCameraImuOptions& options, const Eigen::Isometry3d& camera_in_rig, bool compressed,
                                     const std::string& camera_name = "camera");

// The session as a robot records it: every frame of the rig's camera rendered through its lens before the
// board in a plain room (2 grey levels of noise; mono8, or JPEG where the topic is compressed), its
// camera_info, and the IMU's sensor_msgs/Imu; stamps from 1000 s on. Frames rendered `threads` at once (0:
// the cores). Throws InputError naming the file when it cannot be written.
void writeSimulatedWavedBag(const WavedCameraImuSession& session, const WavedCameraImuOptions& options, const RigDescription& rig,
                            const std::string& path, int threads = 0);

}  // namespace vocal
