#pragma once
// A Kinect / Xtion (or an .oni recording) through OpenNI2: device selection as openni2_camera's
// device_id, video modes, depth-to-colour registration, colour/depth frame sync, streams delivered
// as core images with the device's timestamps, and recording to .oni. OpenNI's headers stay in the
// .cpp file.

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "vocal/core/image.h"
#include "vocal/core/pinhole_camera.h"

namespace vocal {

using DepthMillimetres = Image<std::uint16_t>;  // 0 = no measurement

struct Openni2DeviceInfo {
  std::string uri, vendor, name;
  int usb_vendor_id = 0, usb_product_id = 0;
};

struct Openni2VideoMode {
  int width = 640;
  int height = 480;
  int fps = 30;
};

struct Openni2Options {
  // Empty: the first device; "#N": the N-th (from 1); else a device URI, a serial number, or the path
  // of an .oni recording.
  std::string device_id;
  bool depth_registration = true;           // depth reprojected into the colour camera
  bool color_depth_synchronization = false; // the device pairs colour and depth frames
  Openni2VideoMode color_mode, depth_mode;
};

struct Openni2ColorFrame {
  double device_stamp = 0.0;  // seconds, the device's clock
  int index = 0;
  ColorImage image;
};

struct Openni2DepthFrame {
  double device_stamp = 0.0;
  int index = 0;
  DepthMillimetres depth;
};

class Openni2Device {
 public:
  // Throws InputError when OpenNI2 cannot be initialised (its message included).
  static std::vector<Openni2DeviceInfo> listDevices();

  // Throws InputError naming the device_id and the problem (no device, no match, a mode the device
  // does not offer, registration not supported).
  explicit Openni2Device(const Openni2Options& options);
  ~Openni2Device();
  Openni2Device(const Openni2Device&) = delete;
  Openni2Device& operator=(const Openni2Device&) = delete;

  const Openni2DeviceInfo& info() const;
  const std::string& serial() const;  // empty for a recording
  // What camera_info_manager's names carry after "rgb_" / "depth_" (openni2_camera's form): the serial,
  // or for a recording its file name without folder and extension, other characters than letters,
  // digits and '_' replaced by '_'.
  std::string cameraName() const;
  bool isRecording() const;           // an .oni file is being played
  bool registrationEnabled() const;

  // The callbacks run on OpenNI's threads; a stream is started when first asked for.
  void startColor(std::function<void(const Openni2ColorFrame&)> callback);
  void stopColor();
  void startDepth(std::function<void(const Openni2DepthFrame&)> callback);
  void stopDepth();

  // Intrinsics from the stream's field of view and mode (no distortion): what openni2_camera
  // publishes without a calibration file. Depth uses the colour camera's when registered. A stream
  // that reports no usable field of view (0, as recordings without it do) takes the other stream's
  // when depth is registered to colour (both then describe the colour camera), else the nominal
  // Kinect / Xtion values (colour 525 px, depth 575.8 px at 640 wide); `fallback` then says which
  // and why (empty when the stream's own field of view was used). Always finite.
  PinholeCamera colorCamera(std::string* fallback = nullptr) const;
  PinholeCamera depthCamera(std::string* fallback = nullptr) const;

  // Records the started streams into an .oni file until stopRecording. Throws InputError naming the
  // path when the recorder cannot be created.
  void startRecording(const std::string& path);
  void stopRecording();

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace vocal
