// An OpenNI2 driver plugin with one virtual RGB-D device, so the OpenNI2 driver wrapper and nodelet are
// tested through OpenNI2 itself, without hardware. OpenNI2 loads it from the OpenNI2/Drivers folder
// beside the libOpenNI2.so.0 it was loaded from (the build puts both in devel/lib/vocal_openni2).
//
// Device URI "vocal://virtual/1", serial "VOCAL0001". Streams (30 Hz, frame k):
//   depth 640x480 or 320x240 DEPTH_1_MM: depth(x, y) = 1000 + x + 2 y + k millimetres, 0 on column 0;
//   colour 640x480 RGB888: (x mod 256, y mod 256, k mod 256).
// Timestamps are (k + 1) * 33333 microseconds. Registration (depth to colour) and frame sync are accepted.
// The environment variable VOCAL_VIRTUAL_OPENNI2_NO_FOV=color|depth|both makes those streams report a
// field of view of 0, as recordings without it do; VOCAL_VIRTUAL_OPENNI2_STALL_AFTER=N makes every
// stream stop sending after N frames, as a device pulled off its USB bus does (a stream opened anew,
// as on reopening the device, sends N frames again).

#include <atomic>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <string>
#include <thread>

// ONI_EXPORT_DRIVER uses XnLib's allocation macros, which Debian's headers do not ship.
#define XN_NEW(type, arg) new type(arg)
#define XN_DELETE(p) delete (p)
#include <Driver/OniDriverAPI.h>

namespace {
constexpr const char* kUri = "vocal://virtual/1";
constexpr const char* kSerial = "VOCAL0001";
constexpr float kHorizontalFov = 1.0947858f;  // 2 atan(320 / 525): the ROS default Kinect intrinsics
constexpr float kVerticalFov = 0.8575561f;    // 2 atan(240 / 525)

class VirtualStream : public oni::driver::StreamBase {
 public:
  explicit VirtualStream(OniSensorType type) : type_(type) {
    mode_.pixelFormat = type == ONI_SENSOR_DEPTH ? ONI_PIXEL_FORMAT_DEPTH_1_MM : ONI_PIXEL_FORMAT_RGB888;
    mode_.resolutionX = 640;
    mode_.resolutionY = 480;
    mode_.fps = 30;
  }
  ~VirtualStream() override { stop(); }

  OniStatus start() override {
    if (running_) return ONI_STATUS_OK;
    running_ = true;
    const char* stall = std::getenv("VOCAL_VIRTUAL_OPENNI2_STALL_AFTER");
    stall_after_ = stall ? std::atoi(stall) : -1;
    thread_ = std::thread([this] { produce(); });
    return ONI_STATUS_OK;
  }

  void stop() override {
    running_ = false;
    if (thread_.joinable()) thread_.join();
  }

  int getRequiredFrameSize() override {
    return mode_.resolutionX * mode_.resolutionY * (type_ == ONI_SENSOR_DEPTH ? 2 : 3);
  }

  OniBool isPropertySupported(int id) override {
    return id == ONI_STREAM_PROPERTY_VIDEO_MODE || id == ONI_STREAM_PROPERTY_HORIZONTAL_FOV ||
           id == ONI_STREAM_PROPERTY_VERTICAL_FOV || id == ONI_STREAM_PROPERTY_MIRRORING ||
           (type_ == ONI_SENSOR_DEPTH && id == ONI_STREAM_PROPERTY_MAX_VALUE);
  }

  OniStatus getProperty(int id, void* data, int* size) override {
    switch (id) {
      case ONI_STREAM_PROPERTY_VIDEO_MODE: return copyOut(mode_, data, size);
      case ONI_STREAM_PROPERTY_HORIZONTAL_FOV: return copyOut(reportsFov() ? kHorizontalFov : 0.0f, data, size);
      case ONI_STREAM_PROPERTY_VERTICAL_FOV: return copyOut(reportsFov() ? kVerticalFov : 0.0f, data, size);
      case ONI_STREAM_PROPERTY_MIRRORING: return copyOut(OniBool(FALSE), data, size);
      case ONI_STREAM_PROPERTY_MAX_VALUE: return copyOut(int(10000), data, size);
      default: return ONI_STATUS_NOT_SUPPORTED;
    }
  }

  OniStatus setProperty(int id, const void* data, int size) override {
    if (id == ONI_STREAM_PROPERTY_MIRRORING && size == sizeof(OniBool)) return ONI_STATUS_OK;
    if (id != ONI_STREAM_PROPERTY_VIDEO_MODE || size != sizeof(OniVideoMode)) return ONI_STATUS_NOT_SUPPORTED;
    OniVideoMode wanted;
    std::memcpy(&wanted, data, sizeof(wanted));
    const bool depth = type_ == ONI_SENSOR_DEPTH;
    const bool size_ok = (wanted.resolutionX == 640 && wanted.resolutionY == 480) ||
                         (depth && wanted.resolutionX == 320 && wanted.resolutionY == 240);
    if (!size_ok || wanted.fps != 30 || wanted.pixelFormat != mode_.pixelFormat || running_) return ONI_STATUS_BAD_PARAMETER;
    mode_ = wanted;
    return ONI_STATUS_OK;
  }

 private:
  bool reportsFov() const {
    const char* none = std::getenv("VOCAL_VIRTUAL_OPENNI2_NO_FOV");
    if (!none) return true;
    const std::string which(none);
    return !(which == "both" || which == (type_ == ONI_SENSOR_DEPTH ? "depth" : "color"));
  }

  template <typename T>
  static OniStatus copyOut(const T& value, void* data, int* size) {
    if (*size < static_cast<int>(sizeof(T))) return ONI_STATUS_BAD_PARAMETER;
    std::memcpy(data, &value, sizeof(T));
    *size = sizeof(T);
    return ONI_STATUS_OK;
  }

  void produce() {
    auto next = std::chrono::steady_clock::now();
    for (int k = 0; running_; ++k) {
      next += std::chrono::microseconds(33333);
      std::this_thread::sleep_until(next);
      if (stall_after_ >= 0 && k >= stall_after_) continue;  // unplugged: nothing more arrives
      OniFrame* frame = getServices().acquireFrame();
      if (!frame) continue;
      const int w = mode_.resolutionX, h = mode_.resolutionY;
      frame->sensorType = type_;
      frame->videoMode = mode_;
      frame->width = w;
      frame->height = h;
      frame->cropOriginX = frame->cropOriginY = 0;
      frame->croppingEnabled = FALSE;
      frame->frameIndex = k;
      frame->timestamp = static_cast<uint64_t>(k + 1) * 33333u;
      if (type_ == ONI_SENSOR_DEPTH) {
        frame->stride = w * 2;
        frame->dataSize = w * h * 2;
        auto* depth = static_cast<uint16_t*>(frame->data);
        for (int y = 0; y < h; ++y)
          for (int x = 0; x < w; ++x) depth[y * w + x] = x == 0 ? 0 : static_cast<uint16_t>(1000 + x + 2 * y + k);
      } else {
        frame->stride = w * 3;
        frame->dataSize = w * h * 3;
        auto* rgb = static_cast<uint8_t*>(frame->data);
        for (int y = 0; y < h; ++y) {
          for (int x = 0; x < w; ++x) {
            uint8_t* p = rgb + 3 * (y * w + x);
            p[0] = static_cast<uint8_t>(x % 256), p[1] = static_cast<uint8_t>(y % 256), p[2] = static_cast<uint8_t>(k % 256);
          }
        }
      }
      raiseNewFrame(frame);
      getServices().releaseFrame(frame);
    }
  }

  OniSensorType type_;
  OniVideoMode mode_;
  std::atomic<bool> running_{false};
  int stall_after_ = -1;
  std::thread thread_;
};

class VirtualDevice : public oni::driver::DeviceBase {
 public:
  VirtualDevice() {
    depth_modes_[0] = {ONI_PIXEL_FORMAT_DEPTH_1_MM, 640, 480, 30};
    depth_modes_[1] = {ONI_PIXEL_FORMAT_DEPTH_1_MM, 320, 240, 30};
    color_modes_[0] = {ONI_PIXEL_FORMAT_RGB888, 640, 480, 30};
    sensors_[0] = {ONI_SENSOR_DEPTH, 2, depth_modes_};
    sensors_[1] = {ONI_SENSOR_COLOR, 1, color_modes_};
  }

  OniStatus getSensorInfoList(OniSensorInfo** infos, int* count) override {
    *infos = sensors_;
    *count = 2;
    return ONI_STATUS_OK;
  }

  oni::driver::StreamBase* createStream(OniSensorType type) override {
    if (type != ONI_SENSOR_DEPTH && type != ONI_SENSOR_COLOR) return nullptr;
    return new VirtualStream(type);
  }

  void destroyStream(oni::driver::StreamBase* stream) override { delete stream; }

  OniBool isPropertySupported(int id) override {
    return id == ONI_DEVICE_PROPERTY_IMAGE_REGISTRATION || id == ONI_DEVICE_PROPERTY_SERIAL_NUMBER;
  }

  OniStatus getProperty(int id, void* data, int* size) override {
    if (id == ONI_DEVICE_PROPERTY_SERIAL_NUMBER) {
      const int needed = static_cast<int>(std::strlen(kSerial)) + 1;
      if (*size < needed) return ONI_STATUS_BAD_PARAMETER;
      std::memcpy(data, kSerial, needed);
      *size = needed;
      return ONI_STATUS_OK;
    }
    if (id == ONI_DEVICE_PROPERTY_IMAGE_REGISTRATION && *size >= static_cast<int>(sizeof(OniImageRegistrationMode))) {
      std::memcpy(data, &registration_, sizeof(registration_));
      *size = sizeof(registration_);
      return ONI_STATUS_OK;
    }
    return ONI_STATUS_NOT_SUPPORTED;
  }

  OniStatus setProperty(int id, const void* data, int size) override {
    if (id == ONI_DEVICE_PROPERTY_IMAGE_REGISTRATION && size == sizeof(OniImageRegistrationMode)) {
      std::memcpy(&registration_, data, sizeof(registration_));
      return ONI_STATUS_OK;
    }
    return ONI_STATUS_NOT_SUPPORTED;
  }

  OniBool isImageRegistrationModeSupported(OniImageRegistrationMode) override { return TRUE; }

 private:
  OniVideoMode depth_modes_[2];
  OniVideoMode color_modes_[1];
  OniSensorInfo sensors_[2];
  OniImageRegistrationMode registration_ = ONI_IMAGE_REGISTRATION_OFF;
};

class VirtualDriver : public oni::driver::DriverBase {
 public:
  explicit VirtualDriver(OniDriverServices* services) : DriverBase(services) {}

  OniStatus initialize(oni::driver::DeviceConnectedCallback connected, oni::driver::DeviceDisconnectedCallback disconnected,
                       oni::driver::DeviceStateChangedCallback state_changed, void* cookie) override {
    DriverBase::initialize(connected, disconnected, state_changed, cookie);
    OniDeviceInfo info{};
    std::strncpy(info.uri, kUri, ONI_MAX_STR - 1);
    std::strncpy(info.vendor, "vocal", ONI_MAX_STR - 1);
    std::strncpy(info.name, "virtual RGB-D", ONI_MAX_STR - 1);
    info.usbVendorId = 0x1d27;
    info.usbProductId = 0x0601;
    deviceConnected(&info);
    return ONI_STATUS_OK;
  }

  oni::driver::DeviceBase* deviceOpen(const char* uri, const char*) override {
    return std::strcmp(uri, kUri) == 0 ? new VirtualDevice() : nullptr;
  }

  void deviceClose(oni::driver::DeviceBase* device) override { delete device; }
  void shutdown() override {}

  // Frames of both streams already share their timestamps: a sync group needs no work here.
  void* enableFrameSync(oni::driver::StreamBase**, int) override { return &sync_group_; }
  void disableFrameSync(void*) override {}

 private:
  int sync_group_ = 0;
};
}  // namespace

ONI_EXPORT_DRIVER(VirtualDriver)
