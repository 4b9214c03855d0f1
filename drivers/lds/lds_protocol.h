// The two lasers a TurtleBot 3 is sold with, byte for byte. Both send on their own, 230400 baud, measurements a
// degree apart clockwise seen from above (angle 0 forward); PacketStream turns their bytes into SweepPoints for
// drivers/laser_sweep.h.
//
// LDS-02 (LDROBOT LD08), from LDROBOT's development manual of its LD06/LD08/LD19 family: 47-byte packets, 0x54, the
// version-and-length byte 0x2C (12 points), the rotation speed (degrees a second), the start angle (1/100 degree),
// 12 points of distance (mm) and intensity, the end angle, a timestamp (ms, wrapping at 30000), and a CRC-8
// (polynomial 0x4D, most significant bit first, initial value 0) over the 46 bytes before it. Point i lies at
// start + i * (end - start) / 11, the end taken a turn later when it is below the start.
//
// LDS-01 (Hitachi-LG HLS-LFCD2), from its specification's data table: the host sends 'b' to start it and 'e' to stop
// it; 42-byte packets, 0xFA, the packet's index 0xA0 + n (n = 0..59: degrees 6n to 6n + 5), the rotation speed, six
// readings of intensity, distance (mm) and two reserved bytes, and two check bytes. No public document states how the
// check bytes are computed, so they are not checked: a packet is taken only where the next one's start byte and index
// follow it exactly 42 bytes on (a byte lost or added inside it shows), and a corrupted distance within a packet goes
// unseen (docs/hardware.md).
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "drivers/laser_sweep.h"

namespace corridor::drivers::lds {

enum class Model { kLds01, kLds02 };

// LDS-02.
inline constexpr std::size_t kLd08PacketBytes = 47;
inline constexpr std::uint8_t kLd08Header = 0x54;
inline constexpr std::uint8_t kLd08VerLen = 0x2C;
inline constexpr int kLd08Points = 12;
struct Ld08Packet {
  double speed_deg_s = 0.0;
  double start_deg = 0.0;  // clockwise from forward, [0, 360)
  double end_deg = 0.0;
  std::array<std::uint16_t, kLd08Points> distance_mm{};
  std::array<std::uint8_t, kLd08Points> intensity{};
  std::uint16_t timestamp_ms = 0;
};
// The CRC-8 the LD08 ends its packets with.
std::uint8_t Crc8(std::span<const std::uint8_t> bytes);
// Nothing unless the header, the version-and-length byte and the CRC are right.
std::optional<Ld08Packet> DecodeLd08(std::span<const std::uint8_t, kLd08PacketBytes> bytes);
// Point i's angle, clockwise from forward, [0, 360).
double Ld08Angle(const Ld08Packet& packet, int i);

// LDS-01.
inline constexpr std::size_t kLfcdPacketBytes = 42;
inline constexpr std::uint8_t kLfcdStart = 0xFA;
inline constexpr std::uint8_t kLfcdFirstIndex = 0xA0;
inline constexpr int kLfcdPackets = 60;
inline constexpr int kLfcdReadings = 6;
inline constexpr std::uint8_t kLfcdStartCommand = 'b';
inline constexpr std::uint8_t kLfcdStopCommand = 'e';
struct LfcdPacket {
  int index = 0;            // 0..59: readings at degrees 6 * index + 0..5
  std::uint16_t speed = 0;  // as sent (its unit is not stated; the driver measures the rate itself)
  std::array<std::uint16_t, kLfcdReadings> intensity{};
  std::array<std::uint16_t, kLfcdReadings> distance_mm{};
};
// Nothing unless the start byte and the index are right.
std::optional<LfcdPacket> DecodeLfcd(std::span<const std::uint8_t, kLfcdPacketBytes> bytes);

// Measurements from a byte stream as the serial port delivers it, in pieces of any size. Bytes that do not begin a
// packet that checks (noise, a packet cut by a lost byte) are skipped one at a time. A revolution starts at the first
// measurement whose angle is below the one before it.
class PacketStream {
 public:
  explicit PacketStream(Model model) : model_(model) {}
  // Appends the measurements of the whole packets `bytes` completes to `out`.
  void Push(std::span<const std::uint8_t> bytes, std::vector<SweepPoint>& out);
  std::uint64_t skipped_bytes() const { return skipped_; }
  std::uint64_t packets() const { return packets_; }
  // The last LDS-02 packet's rotation speed; 0 for an LDS-01.
  double speed_deg_s() const { return speed_deg_s_; }

 private:
  // The packet at `at` in pending_ as points, or nothing (not a packet, or too few bytes yet to tell: `wait`).
  bool TakeLd08(std::size_t at, std::vector<SweepPoint>& out);
  bool TakeLfcd(std::size_t at, bool& wait, std::vector<SweepPoint>& out);
  void Emit(double angle_deg, std::uint16_t distance_mm, int quality, std::vector<SweepPoint>& out);

  Model model_;
  std::vector<std::uint8_t> pending_;
  std::optional<double> last_angle_deg_;
  std::uint64_t skipped_ = 0;
  std::uint64_t packets_ = 0;
  double speed_deg_s_ = 0.0;
};

}  // namespace corridor::drivers::lds
