// What is plugged in, read from a /dev and a /sys laid out as udev and the kernel lay them out for two USB serial
// devices (an RPLIDAR's CP2102 with its by-id and corridor names, an Arduino Uno) and a port on no USB device.
#include "drivers/discovery.h"

#include <gtest/gtest.h>

#include <unistd.h>

#include <fstream>

namespace corridor::drivers {
namespace {

namespace fs = std::filesystem;

TEST(DiscoveryTest, SerialPortsComeWithTheirStableNamesUsbIdsAndSuggestedDrivers) {
  const fs::path root = fs::temp_directory_path() / ("corridor_discovery_" + std::to_string(::getpid()));
  fs::remove_all(root);
  const fs::path dev = root / "dev", sys = root / "sys";
  fs::create_directories(dev / "serial/by-id");
  fs::create_directories(dev / "corridor");
  for (const char* tty : {"ttyUSB0", "ttyACM0", "ttyUSB1", "tty0"}) std::ofstream(dev / tty) << "";
  fs::create_symlink("../../ttyUSB0", dev / "serial/by-id/usb-Silicon_Labs_CP2102_USB_to_UART_0001-if00-port0");
  fs::create_symlink("../ttyUSB0", dev / "corridor/rplidar");
  fs::create_symlink("../ttyACM0", dev / "corridor/arduino");
  // sysfs: each tty's device is a USB interface under its USB device, which has the ids.
  const auto usb = [&](const std::string& tty, const std::string& device, const std::string& vendor,
                       const std::string& product) {
    const fs::path interface = sys / "devices/pci0000:00/usb1" / device / (device + ":1.0");
    fs::create_directories(interface / tty);
    std::ofstream(sys / "devices/pci0000:00/usb1" / device / "idVendor") << vendor << "\n";
    std::ofstream(sys / "devices/pci0000:00/usb1" / device / "idProduct") << product << "\n";
    fs::create_directories(sys / "class/tty" / tty);
    fs::create_symlink(interface, sys / "class/tty" / tty / "device");
  };
  usb("ttyUSB0", "1-1", "10c4", "ea60");
  usb("ttyACM0", "1-2", "2341", "0043");
  fs::create_directories(sys / "class/tty/ttyUSB1");  // a port on no USB device

  const std::vector<SerialPortInfo> ports = ListSerialPorts(dev, sys);
  ASSERT_EQ(ports.size(), 3u);
  EXPECT_EQ(ports[0].path, (dev / "ttyACM0").string());
  EXPECT_EQ(ports[0].usb_id, "2341:0043");
  EXPECT_EQ(ports[0].driver, "serial-text");
  EXPECT_EQ(ports[0].names, std::vector<std::string>{(dev / "corridor/arduino").string()});
  EXPECT_EQ(ports[1].path, (dev / "ttyUSB0").string());
  EXPECT_EQ(ports[1].usb_id, "10c4:ea60");
  EXPECT_EQ(ports[1].driver, "rplidar or lds");
  EXPECT_EQ(ports[1].names.size(), 2u);
  EXPECT_EQ(ports[2].usb_id, "");
  EXPECT_EQ(ports[2].driver, "");
  fs::remove_all(root);
  // A machine without any: nothing, and no error.
  EXPECT_TRUE(ListSerialPorts(root / "nowhere", root / "nothing").empty());
}

TEST(DiscoveryTest, AKobukiIsAnFtdiWhoseSerialSaysSo) {
  EXPECT_EQ(SuggestedDriver("0403:6001", "kobuki_A601D8PJ"), "kobuki");
  EXPECT_EQ(SuggestedDriver("0403:6001", "A601D8PJ"), "");
  EXPECT_EQ(SuggestedDriver("0483:5740", ""), "turtlebot3");
  EXPECT_EQ(SuggestedDriver("15d1:0000", ""), "hokuyo");
  EXPECT_EQ(SuggestedDriver("0403:6015", ""), "create2");
}

}  // namespace
}  // namespace corridor::drivers
