#include "drivers/openni2/openni2_camera.h"

#include <OpenNI.h>

#include <cmath>
#include <memory>
#include <numbers>
#include <stdexcept>

#include <opencv2/imgproc.hpp>
#include <spdlog/spdlog.h>

namespace corridor::drivers::openni2 {
namespace {

// OpenNI2 is initialised once per process and counts its users: each driver and each listing holds it.
class OpenNiUser {
 public:
  OpenNiUser() {
    if (openni::OpenNI::initialize() != openni::STATUS_OK) {
      throw std::runtime_error(std::string("OpenNI2 did not start: ") + openni::OpenNI::getExtendedError());
    }
  }
  ~OpenNiUser() { openni::OpenNI::shutdown(); }
  OpenNiUser(const OpenNiUser&) = delete;
  OpenNiUser& operator=(const OpenNiUser&) = delete;
};

std::string Error(const char* what) { return std::string(what) + ": " + openni::OpenNI::getExtendedError(); }

// A stream of `sensor` at the configured size and rate in `format`.
void Start(openni::VideoStream& stream, openni::Device& device, openni::SensorType sensor, openni::PixelFormat format,
           const CameraMountOptions& c, const char* what) {
  if (stream.create(device, sensor) != openni::STATUS_OK) throw std::runtime_error(Error(what));
  openni::VideoMode mode = stream.getVideoMode();
  mode.setResolution(c.width, c.height);
  mode.setFps(c.fps);
  mode.setPixelFormat(format);
  if (stream.setVideoMode(mode) != openni::STATUS_OK) {
    throw std::runtime_error(Error(what) + " (the size, rate or format is not offered)");
  }
  if (stream.start() != openni::STATUS_OK) throw std::runtime_error(Error(what));
}

}  // namespace

std::vector<OpenNi2Device> ListOpenNi2Devices() {
  OpenNiUser user;
  openni::Array<openni::DeviceInfo> devices;
  openni::OpenNI::enumerateDevices(&devices);
  std::vector<OpenNi2Device> out;
  for (int i = 0; i < devices.getSize(); ++i)
    out.push_back({devices[i].getUri(), devices[i].getName(), devices[i].getVendor()});
  return out;
}

OpenNi2Camera::OpenNi2Camera(const OpenNi2Options& options, const Clock& clock)
    : LinkedDevice("openni2", options.uri.empty() ? "any device" : options.uri), options_(options), clock_(clock) {
  const CameraMountOptions& c = options.camera;
  if (!Usable(c) || !(options.stale_s > 0.0) || !(options.silence_s > options.stale_s) ||
      !(options.reconnect_s > 0.0)) {
    throw std::invalid_argument(
        "openni2: size, rate and timeouts must be positive, intrinsics given or fields of view within 0-180 degrees, "
        "and silence_s longer than stale_s");
  }
  info_.camera = ToPinhole(c);
  info_.min_range_m = c.min_range_m;
  info_.max_range_m = c.max_range_m;
  thread_ = std::jthread([this](std::stop_token stop) { Run(stop); });
}

OpenNi2Camera::~OpenNi2Camera() {
  thread_.request_stop();
  if (thread_.joinable()) thread_.join();
}

void OpenNi2Camera::SetFrameHandler(FrameHandler handler) {
  std::lock_guard lock(mutex_);
  handler_ = std::move(handler);
}

void OpenNi2Camera::Run(std::stop_token stop) {
  RunSessions(stop, options_.reconnect_s, [&] { Session(stop); });
}

void OpenNi2Camera::Session(std::stop_token stop) {
  SetState(LinkState::kConnecting);
  OpenNiUser user;
  openni::Device device;
  if (device.open(options_.uri.empty() ? openni::ANY_DEVICE : options_.uri.c_str()) != openni::STATUS_OK) {
    throw std::runtime_error(Error("no OpenNI2 device to open"));
  }
  const CameraMountOptions& c = options_.camera;
  openni::VideoStream depth;
  Start(depth, device, openni::SENSOR_DEPTH, openni::PIXEL_FORMAT_DEPTH_1_MM, c, "the depth stream");
  spdlog::info("openni2: {} ({}): depth {}x{} at {} Hz, its fields of view {:.1f} x {:.1f} degrees",
               device.getDeviceInfo().getName(), device.getDeviceInfo().getUri(), c.width, c.height, c.fps,
               depth.getHorizontalFieldOfView() * 180.0 / std::numbers::pi,
               depth.getVerticalFieldOfView() * 180.0 / std::numbers::pi);
  openni::VideoStream color;
  bool registered = false;
  if (options_.color) {
    Start(color, device, openni::SENSOR_COLOR, openni::PIXEL_FORMAT_RGB888, c, "the colour stream");
    if (device.isImageRegistrationModeSupported(openni::IMAGE_REGISTRATION_DEPTH_TO_COLOR)) {
      registered = device.setImageRegistrationMode(openni::IMAGE_REGISTRATION_DEPTH_TO_COLOR) == openni::STATUS_OK;
    }
    device.setDepthColorSyncEnabled(true);
  }
  {
    std::lock_guard lock(mutex_);
    status_.device = std::string(device.getDeviceInfo().getName()) + " " + device.getDeviceInfo().getUri();
    status_.registered = registered;
  }
  cv::Mat latest_color(c.height, c.width, CV_8UC3, cv::Scalar::all(0));
  TimeNs last_frame_ns = clock_.Now();
  std::uint64_t sequence = 0;
  openni::VideoStream* streams[] = {&depth, &color};
  const int count = options_.color ? 2 : 1;
  while (!stop.stop_requested()) {
    int ready = -1;
    const openni::Status waited =
        openni::OpenNI::waitForAnyStream(streams, count, &ready, static_cast<int>(options_.stale_s * 500.0));
    const TimeNs now = clock_.Now();
    if (waited == openni::STATUS_OK && ready == 1) {
      openni::VideoFrameRef frame;
      if (color.readFrame(&frame) == openni::STATUS_OK && frame.getWidth() == c.width &&
          frame.getHeight() == c.height) {
        const cv::Mat rgb(c.height, c.width, CV_8UC3, const_cast<void*>(frame.getData()),
                          static_cast<std::size_t>(frame.getStrideInBytes()));
        cv::cvtColor(rgb, latest_color, cv::COLOR_RGB2BGR);
      }
      continue;
    }
    if (waited != openni::STATUS_OK || ready != 0) {
      const double quiet_s = ToSeconds(now - last_frame_ns);
      if (quiet_s >= options_.silence_s) {
        SetState(LinkState::kSilent,
                 fmt::format("no depth frame for {:.1f} s: opening the device anew", options_.silence_s));
        return;
      }
      if (quiet_s >= options_.stale_s) {
        SetState(LinkState::kStale, fmt::format("no depth frame for {:.0f} ms", options_.stale_s * 1e3));
      }
      continue;
    }
    openni::VideoFrameRef d;
    if (depth.readFrame(&d) != openni::STATUS_OK || d.getWidth() != c.width || d.getHeight() != c.height) continue;
    last_frame_ns = now;
    auto out = std::make_shared<RgbdFrame>();
    out->stamp_ns = now;
    out->sequence = sequence++;
    cv::Mat(c.height, c.width, CV_16UC1, const_cast<void*>(d.getData()), static_cast<std::size_t>(d.getStrideInBytes()))
        .copyTo(out->depth_mm);
    out->color_bgr = latest_color.clone();
    FrameHandler handler;
    {
      std::lock_guard lock(mutex_);
      ++status_.frames;
      handler = handler_;
    }
    SetState(LinkState::kRunning);
    if (handler) handler(std::move(out));
  }
  depth.stop();
  if (options_.color) color.stop();
}

}  // namespace corridor::drivers::openni2
