// A host's request to one DYNAMIXEL device and the wait for its answer, over a byte stream (the serial port): what
// a driver does while it sets its device up, before it streams.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <vector>

#include "drivers/clock.h"
#include "drivers/dynamixel/dynamixel_protocol.h"
#include "drivers/serial/byte_stream.h"

namespace corridor::drivers::dynamixel {

struct Answer {
  std::optional<StatusPacket> status;  // none: no answer came in time, or the device refused
  bool refused = false;                // its error byte said why (status.error's low 7 bits not 0)
  std::uint8_t error = 0;              // that error byte, alert bit included
};

// Sends `request` to device `id` and waits up to timeout_s on `clock` for its status with `parameters` bytes
// (answers of other sizes, late ones to earlier requests, are passed over).
Answer Transact(ByteStream& port, StatusParser& parser, const Clock& clock, std::uint8_t id,
                const std::vector<std::uint8_t>& request, std::size_t parameters, double timeout_s);

}  // namespace corridor::drivers::dynamixel
