#include "drivers/lds/lds_laser.h"

#include <array>
#include <vector>

namespace corridor::drivers::lds {

LdsLaser::LdsLaser(const LdsOptions& options, const Clock& clock)
    : RotatingLaser("lds", {options.port, options.stale_s, options.silence_s, options.reconnect_s},
                    options.base_T_laser, options.height_m, options.sweep, clock),
      options_(options) {
  thread_ = std::jthread([this](std::stop_token stop) {
    RunPortSessions(stop, options_.baud_rate, [&](SerialPort& port) { Scan(port, stop); });
  });
}

LdsLaser::~LdsLaser() {
  thread_.request_stop();
  if (thread_.joinable()) thread_.join();
}

void LdsLaser::Scan(SerialPort& port, std::stop_token stop) {
  const bool lds01 = options_.model == Model::kLds01;
  if (lds01) port.Write(std::array<std::uint8_t, 1>{kLfcdStartCommand});
  PacketStream packets(options_.model);
  ReadSweeps(
      port, stop, {},
      [&](std::span<const std::uint8_t> bytes, std::vector<SweepPoint>& points) {
        const std::uint64_t before = packets.packets();
        packets.Push(bytes, points);
        return packets.packets() - before;
      },
      [&](LdsStatus& status) {
        status.packets = packets.packets();
        status.skipped_bytes = packets.skipped_bytes();
        status.speed_deg_s = packets.speed_deg_s();
      });
  if (lds01) port.Write(std::array<std::uint8_t, 1>{kLfcdStopCommand});
}

}  // namespace corridor::drivers::lds
