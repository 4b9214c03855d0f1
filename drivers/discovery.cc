#include "drivers/discovery.h"

#include <algorithm>
#include <fstream>
#include <system_error>

namespace corridor::drivers {
namespace fs = std::filesystem;
namespace {

std::string FirstLine(const fs::path& file) {
  std::ifstream in(file);
  std::string line;
  std::getline(in, line);
  return line;
}

// The USB device a tty hangs off: the nearest directory above its sysfs device with an idVendor.
fs::path UsbDevice(const fs::path& sys, const std::string& tty) {
  std::error_code ec;
  fs::path at = fs::canonical(sys / "class/tty" / tty / "device", ec);
  for (int up = 0; !ec && up < 4 && !at.empty() && at != at.root_path(); ++up, at = at.parent_path()) {
    if (fs::exists(at / "idVendor", ec)) return at;
  }
  return {};
}

}  // namespace

std::string SuggestedDriver(const std::string& usb_id, const std::string& serial) {
  if (usb_id == "10c4:ea60") return "rplidar or lds";  // a TurtleBot 3's USB2LDS board is a CP210x too
  if (usb_id == "0403:6015") return "create2";
  if (usb_id == "0403:6001" && serial.starts_with("kobuki")) return "kobuki";
  if (usb_id == "0483:5740") return "turtlebot3";
  if (usb_id == "15d1:0000") return "hokuyo";
  if (usb_id.starts_with("2341:") || usb_id.starts_with("2a03:")) return "serial-text";
  return "";
}

std::vector<SerialPortInfo> ListSerialPorts(const fs::path& dev, const fs::path& sys) {
  std::vector<SerialPortInfo> ports;
  std::error_code ec;
  for (const fs::directory_entry& entry : fs::directory_iterator(dev, ec)) {
    const std::string name = entry.path().filename().string();
    if (!name.starts_with("ttyUSB") && !name.starts_with("ttyACM")) continue;
    SerialPortInfo port;
    port.path = entry.path().string();
    if (const fs::path usb = UsbDevice(sys, name); !usb.empty()) {
      port.usb_id = FirstLine(usb / "idVendor") + ":" + FirstLine(usb / "idProduct");
      port.driver = SuggestedDriver(port.usb_id, FirstLine(usb / "serial"));
    }
    ports.push_back(std::move(port));
  }
  // The stable names pointing at each.
  for (const fs::path& folder : {dev / "corridor", dev / "serial/by-id"}) {
    for (const fs::directory_entry& link : fs::directory_iterator(folder, ec)) {
      std::error_code link_ec;
      const fs::path target = fs::canonical(link.path(), link_ec);
      if (link_ec) continue;
      for (SerialPortInfo& port : ports) {
        if (fs::canonical(port.path, link_ec) == target) port.names.push_back(link.path().string());
      }
    }
    ec.clear();
  }
  std::sort(ports.begin(), ports.end(), [](const SerialPortInfo& a, const SerialPortInfo& b) {
    return a.path.size() != b.path.size() ? a.path.size() < b.path.size() : a.path < b.path;
  });
  return ports;
}

}  // namespace corridor::drivers
