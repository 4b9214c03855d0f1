#include "drivers/dynamixel/dynamixel_link.h"

#include <array>
#include <span>

namespace corridor::drivers::dynamixel {

Answer Transact(ByteStream& port, StatusParser& parser, const Clock& clock, std::uint8_t id,
                const std::vector<std::uint8_t>& request, std::size_t parameters, double timeout_s) {
  port.Write(request);
  std::vector<StatusPacket> got;
  std::array<std::uint8_t, 256> buffer{};
  const TimeNs give_up = clock.Now() + FromSeconds(timeout_s);
  for (TimeNs now = clock.Now(); now < give_up; now = clock.Now()) {
    const std::size_t n = port.Read(buffer, ToSeconds(give_up - now));
    got.clear();
    parser.Push(std::span<const std::uint8_t>(buffer.data(), n), got);
    for (StatusPacket& status : got) {
      // A refusal (its error byte) comes without the parameters asked for.
      if (status.id == id && (status.error & ~kAlertBit) != 0) return {std::nullopt, true, status.error};
      if (status.id != id || status.parameters.size() != parameters) continue;
      const std::uint8_t error = status.error;
      return {std::move(status), false, error};
    }
  }
  return {};
}

}  // namespace corridor::drivers::dynamixel
