// What is plugged in, for setting the robot up (the console's Devices view, GET /api/v1/devices/hardware): the serial
// ports with their stable names (udev's /dev/serial/by-id and the package's /dev/corridor) and USB ids, with the
// driver a port's USB id suggests; and the video nodes with their names and formats. Read from /dev and /sys (roots
// given for tests).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace corridor::drivers {

struct SerialPortInfo {
  std::string path;                // /dev/ttyUSB0
  std::vector<std::string> names;  // the links to it: /dev/corridor/rplidar, /dev/serial/by-id/usb-...
  std::string usb_id;              // vendor:product, "" when not on USB
  std::string driver;              // the driver its USB id suggests ("" when none does)
};

// Every /dev/ttyUSB* and /dev/ttyACM*, in order of their names.
std::vector<SerialPortInfo> ListSerialPorts(const std::filesystem::path& dev = "/dev",
                                            const std::filesystem::path& sys = "/sys");
// The driver a USB serial device's vendor:product (and serial number) suggests: "rplidar or lds" (the same chip),
// create2, kobuki, turtlebot3, serial-text, hokuyo, or "".
std::string SuggestedDriver(const std::string& usb_id, const std::string& serial);

}  // namespace corridor::drivers
