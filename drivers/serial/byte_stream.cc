#include "drivers/serial/byte_stream.h"

#include <charconv>
#include <stdexcept>

#include "drivers/serial/serial_port.h"
#include "drivers/serial/tcp_stream.h"

namespace corridor::drivers {

std::unique_ptr<ByteStream> OpenStream(const std::string& port, int baud_rate, double connect_s) {
  if (!IsNetworkPort(port)) return std::make_unique<SerialPort>(port, baud_rate);
  const std::size_t colon = port.rfind(':');
  int number = 0;
  const char* end = port.data() + port.size();
  const auto [at, e] = std::from_chars(port.data() + colon + 1, end, number);
  if (e != std::errc{} || at != end || number <= 0 || number > 65535) {
    throw std::invalid_argument("'" + port + "': the port after the colon is not a TCP port number");
  }
  return std::make_unique<TcpStream>(port.substr(0, colon), number, connect_s);
}

}  // namespace corridor::drivers
