#include "vocal/driver/openni2_device.h"

#include <cctype>
#include <cmath>
#include <cstring>
#include <mutex>
#include <sstream>
#include <sys/stat.h>

#include <OpenNI.h>

#include "vocal/core/errors.h"

namespace vocal {

namespace {
std::string lastError() { return openni::OpenNI::getExtendedError(); }

// OpenNI2 is a process-wide library: initialised once, on first use.
void initializeOpenNi() {
  static std::once_flag once;
  static std::string failure;
  std::call_once(once, [] {
    if (openni::OpenNI::initialize() != openni::STATUS_OK) failure = "OpenNI2 could not be initialised: " + lastError();
  });
  if (!failure.empty()) throw InputError(failure);
}

Openni2DeviceInfo toInfo(const openni::DeviceInfo& info) {
  return {info.getUri(), info.getVendor(), info.getName(), info.getUsbVendorId(), info.getUsbProductId()};
}

bool isExistingFile(const std::string& path) {
  struct stat st {};
  return ::stat(path.c_str(), &st) == 0 && S_ISREG(st.st_mode);
}

std::string readSerial(openni::Device& device) {
  char serial[ONI_MAX_STR] = {};
  int size = sizeof(serial);
  if (device.getProperty(ONI_DEVICE_PROPERTY_SERIAL_NUMBER, serial, &size) != openni::STATUS_OK) return "";
  return std::string(serial);
}

// Nominal focal lengths at 640 pixels wide (openni_camera's Kinect / PrimeSense values).
constexpr double kNominalColorFocal640 = 525.0;
constexpr double kNominalDepthFocal640 = 575.8157;

// A field of view OpenNI reports, in radians, usable for intrinsics: recordings without it report 0.
bool usableFov(float radians) { return std::isfinite(radians) && radians > 0.01f && radians < 3.1f; }

bool hasUsableFov(const openni::VideoStream& stream) {
  return usableFov(stream.getHorizontalFieldOfView()) && usableFov(stream.getVerticalFieldOfView());
}

std::string fovText(const openni::VideoStream& stream) {
  std::ostringstream text;
  text << stream.getHorizontalFieldOfView() << " x " << stream.getVerticalFieldOfView() << " rad";
  return text.str();
}

// Pinhole intrinsics at the stream's resolution, pixel centres at (w-1)/2: from the field of view
// (`fov_from`, which may be the other stream) or, with none, a nominal focal length at 640 wide.
PinholeCamera streamCamera(const openni::VideoStream& stream, const openni::VideoStream* fov_from, double nominal_focal_640) {
  const openni::VideoMode mode = stream.getVideoMode();
  PinholeCamera camera;
  camera.width = mode.getResolutionX();
  camera.height = mode.getResolutionY();
  if (fov_from) {
    camera.fx = 0.5 * camera.width / std::tan(0.5 * fov_from->getHorizontalFieldOfView());
    camera.fy = 0.5 * camera.height / std::tan(0.5 * fov_from->getVerticalFieldOfView());
  } else {
    camera.fx = camera.fy = nominal_focal_640 * camera.width / 640.0;
  }
  camera.cx = 0.5 * (camera.width - 1);
  camera.cy = 0.5 * (camera.height - 1);
  camera.depth_scale = 1000.0;
  return camera;
}

std::string fileStem(const std::string& path) {
  std::string stem = path.substr(path.find_last_of('/') + 1);
  const std::size_t dot = stem.find_last_of('.');
  if (dot != std::string::npos && dot > 0) stem.resize(dot);
  for (char& c : stem)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_') c = '_';
  return stem;
}

class FrameListener : public openni::VideoStream::NewFrameListener {
 public:
  explicit FrameListener(std::function<void(const openni::VideoFrameRef&)> handler) : handler_(std::move(handler)) {}
  void onNewFrame(openni::VideoStream& stream) override {
    openni::VideoFrameRef frame;
    if (stream.readFrame(&frame) == openni::STATUS_OK && frame.isValid()) handler_(frame);
  }

 private:
  std::function<void(const openni::VideoFrameRef&)> handler_;
};
}  // namespace

struct Openni2Device::Impl {
  openni::Device device;
  openni::VideoStream color, depth;
  std::unique_ptr<FrameListener> color_listener, depth_listener;
  openni::Recorder recorder;
  Openni2DeviceInfo info;
  std::string serial;
  bool registration = false;
  bool has_color = false, has_depth = false;
  std::string what;  // "device_id '...'" for messages

  void setMode(openni::VideoStream& stream, openni::SensorType type, const Openni2VideoMode& wanted, const char* name) {
    const openni::SensorInfo& sensor = stream.getSensorInfo();
    const openni::Array<openni::VideoMode>& modes = sensor.getSupportedVideoModes();
    std::ostringstream offered;
    for (int i = 0; i < modes.getSize(); ++i) {
      const openni::VideoMode& m = modes[i];
      const bool usable = type == openni::SENSOR_DEPTH ? m.getPixelFormat() == openni::PIXEL_FORMAT_DEPTH_1_MM
                                                      : m.getPixelFormat() == openni::PIXEL_FORMAT_RGB888;
      if (!usable) continue;
      if (m.getResolutionX() == wanted.width && m.getResolutionY() == wanted.height && m.getFps() == wanted.fps) {
        if (stream.setVideoMode(m) != openni::STATUS_OK) {
          throw InputError(what + ": the " + name + " mode could not be set: " + lastError());
        }
        return;
      }
      offered << (offered.str().empty() ? "" : ", ") << m.getResolutionX() << "x" << m.getResolutionY() << "@" << m.getFps();
    }
    std::ostringstream message;
    message << what << ": " << name << " mode " << wanted.width << "x" << wanted.height << "@" << wanted.fps
            << " is not offered (offered: " << offered.str() << ")";
    throw InputError(message.str());
  }
};

std::vector<Openni2DeviceInfo> Openni2Device::listDevices() {
  initializeOpenNi();
  openni::Array<openni::DeviceInfo> devices;
  openni::OpenNI::enumerateDevices(&devices);
  std::vector<Openni2DeviceInfo> out;
  for (int i = 0; i < devices.getSize(); ++i) out.push_back(toInfo(devices[i]));
  return out;
}

Openni2Device::Openni2Device(const Openni2Options& options) : impl_(std::make_unique<Impl>()) {
  Impl& d = *impl_;
  d.what = "device_id '" + options.device_id + "'";
  const std::vector<Openni2DeviceInfo> devices = listDevices();
  std::string uri;
  const std::string& id = options.device_id;
  if (!id.empty() && isExistingFile(id)) {
    uri = id;  // an .oni recording
  } else if (id.empty() || id[0] == '#') {
    int index = 1;
    if (!id.empty()) {
      try {
        std::size_t used = 0;
        index = std::stoi(id.substr(1), &used);
        if (used != id.size() - 1) throw std::invalid_argument(id);
      } catch (const std::exception&) {
        throw InputError(d.what + ": '#' must be followed by a device number from 1");
      }
    }
    if (devices.empty()) throw InputError(d.what + ": no OpenNI2 device is connected");
    if (index < 1 || index > static_cast<int>(devices.size())) {
      throw InputError(d.what + ": there is no device " + std::to_string(index) + ", " + std::to_string(devices.size()) +
                       " connected");
    }
    uri = devices[index - 1].uri;
  } else {
    for (const Openni2DeviceInfo& info : devices)
      if (info.uri == id) uri = id;
    if (uri.empty()) {
      // A serial number: open each device to read its serial, as openni2_camera does.
      std::string serials;
      for (const Openni2DeviceInfo& info : devices) {
        openni::Device probe;
        if (probe.open(info.uri.c_str()) != openni::STATUS_OK) continue;
        const std::string serial = probe.isFile() ? "" : readSerial(probe);  // recordings open in this process
        probe.close();
        if (serial.empty()) continue;
        serials += (serials.empty() ? "" : ", ") + serial;
        if (serial == id) uri = info.uri;
      }
      if (uri.empty()) {
        throw InputError(d.what + ": no connected device has this URI or serial, and no such .oni file exists (connected: " +
                         (serials.empty() ? "none" : serials) + ")");
      }
    }
  }
  if (d.device.open(uri.c_str()) != openni::STATUS_OK) throw InputError(d.what + ": cannot open " + uri + ": " + lastError());
  d.info = toInfo(d.device.getDeviceInfo());
  if (!d.device.isFile()) d.serial = readSerial(d.device);

  // A live device must offer both streams; a recording holds those that were recorded.
  const bool file = d.device.isFile();
  d.has_color = d.color.create(d.device, openni::SENSOR_COLOR) == openni::STATUS_OK;
  if (!d.has_color && !file) throw InputError(d.what + ": the device has no colour stream: " + lastError());
  d.has_depth = d.depth.create(d.device, openni::SENSOR_DEPTH) == openni::STATUS_OK;
  if (!d.has_depth && !file) throw InputError(d.what + ": the device has no depth stream: " + lastError());
  if (!d.device.isFile()) {
    d.setMode(d.color, openni::SENSOR_COLOR, options.color_mode, "colour");
    d.setMode(d.depth, openni::SENSOR_DEPTH, options.depth_mode, "depth");
    if (options.depth_registration) {
      if (!d.device.isImageRegistrationModeSupported(openni::IMAGE_REGISTRATION_DEPTH_TO_COLOR) ||
          d.device.setImageRegistrationMode(openni::IMAGE_REGISTRATION_DEPTH_TO_COLOR) != openni::STATUS_OK) {
        throw InputError(d.what + ": depth registration is not supported by this device; set depth_registration false");
      }
    }
    if (options.color_depth_synchronization && d.device.setDepthColorSyncEnabled(true) != openni::STATUS_OK) {
      throw InputError(d.what + ": colour/depth synchronisation could not be enabled: " + lastError());
    }
  }
  d.registration = d.device.getImageRegistrationMode() == openni::IMAGE_REGISTRATION_DEPTH_TO_COLOR;
}

Openni2Device::~Openni2Device() {
  stopRecording();
  stopColor();
  stopDepth();
  if (impl_->has_color) impl_->color.destroy();
  if (impl_->has_depth) impl_->depth.destroy();
  impl_->device.close();
}

const Openni2DeviceInfo& Openni2Device::info() const { return impl_->info; }
const std::string& Openni2Device::serial() const { return impl_->serial; }
bool Openni2Device::isRecording() const { return impl_->device.isFile(); }

std::string Openni2Device::cameraName() const {
  if (!impl_->serial.empty()) return impl_->serial;
  const std::string stem = fileStem(impl_->info.uri);
  return stem.empty() ? "unknown" : stem;
}
bool Openni2Device::registrationEnabled() const { return impl_->registration; }

namespace {
// A frame's rows copied into an image of pixels of sizeof(Pixel) bytes, with its stamp and index.
template <typename Frame, typename Pixel>
Frame copyFrame(const openni::VideoFrameRef& frame, Image<Pixel> Frame::*image) {
  Frame out;
  out.device_stamp = frame.getTimestamp() * 1e-6;
  out.index = frame.getFrameIndex();
  Image<Pixel>& pixels = out.*image;
  pixels = Image<Pixel>(frame.getWidth(), frame.getHeight());
  const auto* data = static_cast<const std::uint8_t*>(frame.getData());
  for (int y = 0; y < frame.getHeight(); ++y) {
    std::memcpy(&pixels(0, y), data + static_cast<std::size_t>(y) * frame.getStrideInBytes(), sizeof(Pixel) * frame.getWidth());
  }
  return out;
}

// Listens on `stream` and starts it; undone when the start fails.
void startStream(openni::VideoStream& stream, std::unique_ptr<FrameListener>* listener, FrameListener* fresh,
                 const std::string& what, const char* name) {
  listener->reset(fresh);
  stream.addNewFrameListener(fresh);
  if (stream.start() != openni::STATUS_OK) {
    stream.removeNewFrameListener(fresh);
    listener->reset();
    throw InputError(what + ": the " + name + " stream could not start: " + lastError());
  }
}

// The listener goes first: stopping a stream while its callback may still run, then unregistering,
// can deadlock inside OpenNI2 (a callback's readFrame against the unregistering thread); openni2_camera
// uses the same order.
void stopStream(openni::VideoStream& stream, std::unique_ptr<FrameListener>* listener) {
  if (!*listener) return;
  stream.removeNewFrameListener(listener->get());
  stream.stop();
  listener->reset();
}
}  // namespace

void Openni2Device::startColor(std::function<void(const Openni2ColorFrame&)> callback) {
  Impl& d = *impl_;
  if (d.color_listener) return;
  if (!d.has_color) throw InputError(d.what + ": the recording holds no colour stream");
  startStream(d.color, &d.color_listener, new FrameListener([callback](const openni::VideoFrameRef& frame) {
                callback(copyFrame(frame, &Openni2ColorFrame::image));
              }),
              d.what, "colour");
}

void Openni2Device::stopColor() { stopStream(impl_->color, &impl_->color_listener); }

void Openni2Device::startDepth(std::function<void(const Openni2DepthFrame&)> callback) {
  Impl& d = *impl_;
  if (d.depth_listener) return;
  if (!d.has_depth) throw InputError(d.what + ": the recording holds no depth stream");
  startStream(d.depth, &d.depth_listener, new FrameListener([callback](const openni::VideoFrameRef& frame) {
                callback(copyFrame(frame, &Openni2DepthFrame::depth));
              }),
              d.what, "depth");
}

void Openni2Device::stopDepth() { stopStream(impl_->depth, &impl_->depth_listener); }

PinholeCamera Openni2Device::colorCamera(std::string* fallback) const {
  const Impl& d = *impl_;
  if (!d.has_color) throw InputError(d.what + ": the recording holds no colour stream");
  if (fallback) fallback->clear();
  if (hasUsableFov(d.color)) return streamCamera(d.color, &d.color, kNominalColorFocal640);
  const bool from_depth = d.registration && d.has_depth && hasUsableFov(d.depth);
  if (fallback) {
    *fallback = "the colour stream reports no usable field of view (" + fovText(d.color) + "): intrinsics from " +
                (from_depth ? "the registered depth stream's" : "the nominal Kinect / Xtion colour focal length (525 px at 640 wide)");
  }
  return streamCamera(d.color, from_depth ? &d.depth : nullptr, kNominalColorFocal640);
}

PinholeCamera Openni2Device::depthCamera(std::string* fallback) const {
  const Impl& d = *impl_;
  if (!d.has_depth) throw InputError(d.what + ": the recording holds no depth stream");
  if (fallback) fallback->clear();
  const openni::VideoMode mode = d.depth.getVideoMode();
  if (d.registration && d.has_color) {
    // Registered depth lies in the colour camera, at the depth stream's resolution.
    const PinholeCamera color = colorCamera(fallback);
    if (fallback && !fallback->empty()) *fallback = "registered depth: " + *fallback;
    return color.scaled(static_cast<double>(mode.getResolutionX()) / color.width);
  }
  if (hasUsableFov(d.depth)) return streamCamera(d.depth, &d.depth, kNominalDepthFocal640);
  if (fallback) {
    *fallback = "the depth stream reports no usable field of view (" + fovText(d.depth) +
                "): intrinsics from the nominal Kinect / Xtion depth focal length (575.8 px at 640 wide)";
  }
  return streamCamera(d.depth, nullptr, kNominalDepthFocal640);
}

void Openni2Device::startRecording(const std::string& path) {
  Impl& d = *impl_;
  if (d.recorder.isValid()) return;
  if (d.recorder.create(path.c_str()) != openni::STATUS_OK) {
    throw InputError(path + ": cannot create the .oni recording: " + lastError());
  }
  if (d.color_listener) d.recorder.attach(d.color, false);
  if (d.depth_listener) d.recorder.attach(d.depth, false);
  if (d.recorder.start() != openni::STATUS_OK) {
    d.recorder.destroy();
    throw InputError(path + ": the recording could not start: " + lastError());
  }
}

void Openni2Device::stopRecording() {
  Impl& d = *impl_;
  if (!d.recorder.isValid()) return;
  d.recorder.stop();
  d.recorder.destroy();
}

}  // namespace vocal
