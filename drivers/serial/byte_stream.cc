#include "drivers/serial/byte_stream.h"

#include <stdexcept>

#include "drivers/serial/serial_port.h"
#include "drivers/serial/tcp_stream.h"

namespace corridor::drivers {

std::unique_ptr<ByteStream> OpenStream(const std::string& port, int baud_rate, double connect_s) {
  if (!IsNetworkPort(port)) return std::make_unique<SerialPort>(port, baud_rate);
  const std::optional<int> number = NetworkPortNumber(port);
  if (!number) throw std::invalid_argument("'" + port + "': the port after the colon is not a TCP port number");
  return std::make_unique<TcpStream>(port.substr(0, port.rfind(':')), *number, connect_s);
}

}  // namespace corridor::drivers
