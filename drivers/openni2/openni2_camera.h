// A depth camera through OpenNI2 (Debian's libopenni2: its PS1080 driver for the Asus Xtion, PrimeSense Carmine and
// Orbbec Astra; a Kinect v1 through libfreenect's OpenNI2 driver where installed): the driver's thread opens the
// device (its URI, or the first), streams depth in millimetres and, if asked, colour registered to the depth where the
// device supports it, and hands on each depth frame with the newest colour frame. The intrinsics come from the
// configuration (a calibration, or the fields of view; the device's own fields of view are logged when it opens, to
// compare). A device that stops sending frames for silence_s, or is not there, is opened anew every reconnect_s.
#pragma once

#include <cstdint>
#include <mutex>
#include <string>
#include <thread>

#include "drivers/depth_camera.h"
#include "drivers/openni2/openni2_options.h"
#include "drivers/serial/linked_device.h"

namespace corridor::drivers::openni2 {

struct OpenNi2Status : LinkStatus {
  std::uint64_t frames = 0;  // depth frames handed on
  std::string device;        // the open device's name and URI
  bool registered = false;   // the colour is registered to the depth
};

// The OpenNI2 devices plugged in: each one's URI and name (none without OpenNI2's drivers or devices).
struct OpenNi2Device {
  std::string uri;
  std::string name;
  std::string vendor;
};
std::vector<OpenNi2Device> ListOpenNi2Devices();

class OpenNi2Camera final : public DepthCamera, public LinkedDevice<OpenNi2Status> {
 public:
  // Starts the driver's thread; `clock` stamps the frames and must outlive it. Throws std::invalid_argument for
  // options that cannot work, std::runtime_error when OpenNI2 itself cannot start.
  OpenNi2Camera(const OpenNi2Options& options, const Clock& clock);
  ~OpenNi2Camera() override;

  CameraInfo info() const override { return info_; }
  void SetFrameHandler(FrameHandler handler) override;

 private:
  void Run(std::stop_token stop);
  void Session(std::stop_token stop);

  const OpenNi2Options options_;
  const Clock& clock_;
  CameraInfo info_;
  FrameHandler handler_;
  std::jthread thread_;  // last: started after everything it uses
};

}  // namespace corridor::drivers::openni2
