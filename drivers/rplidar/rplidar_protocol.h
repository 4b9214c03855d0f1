// The Slamtec RPLIDAR serial protocol, from Slamtec's public "RPLIDAR Interface Protocol and Application Notes":
// requests, response descriptors, the device's information and health, the standard scan's 5-byte measurement nodes
// and the legacy express scan's 84-byte capsules, assembled into sweeps. Bytes in and out only: the driver does the
// I/O, and the emulator in the tests speaks the device's side from the same document (written apart from this code,
// so that a misreading shows as a mismatch; where both read the document the same wrong way, only a real device
// tells, and docs/hardware.md says which readings were not checked against one).
//
// Scans from the device are clockwise seen from above (angle 0 forward): drivers/laser_sweep.h makes them LaserScans.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "drivers/laser_sweep.h"

namespace corridor::drivers::rplidar {

inline constexpr std::uint8_t kStartFlag1 = 0xA5;
inline constexpr std::uint8_t kStartFlag2 = 0x5A;

enum class Command : std::uint8_t {
  kStop = 0x25,
  kReset = 0x40,
  kScan = 0x20,
  kForceScan = 0x21,
  kGetInfo = 0x50,
  kGetHealth = 0x52,
  kGetSampleRate = 0x59,
  kExpressScan = 0x82,  // firmware 1.17 on: twice the standard scan's samples a second (an A1's 4000), in capsules
  kSetMotorPwm = 0xF0,  // A2/A3: the motor's duty (0-1023) as a 16-bit little-endian payload; the A1 uses DTR
};

// A request: A5 and the command; with a payload, its size, the payload, and the XOR of every byte before it.
std::vector<std::uint8_t> EncodeRequest(Command command, std::span<const std::uint8_t> payload = {});

// The response descriptor that answers a request: A5 5A, a 30-bit length and 2-bit send mode (little endian), and the
// data type.
enum class DataType : std::uint8_t { kInfo = 0x04, kHealth = 0x06, kSampleRate = 0x15, kScan = 0x81, kCapsule = 0x82 };
struct Descriptor {
  std::uint32_t length = 0;  // bytes in one response
  bool repeated = false;     // send mode 1: responses follow one another until the device is stopped
  std::uint8_t type = 0;     // DataType
};
inline constexpr std::size_t kDescriptorBytes = 7;
std::array<std::uint8_t, kDescriptorBytes> EncodeDescriptor(const Descriptor& descriptor);
// Nothing unless the bytes begin with A5 5A.
std::optional<Descriptor> DecodeDescriptor(std::span<const std::uint8_t, kDescriptorBytes> bytes);

// GET_INFO's 20 bytes.
struct DeviceInfo {
  int model = 0;
  int firmware_major = 0;
  int firmware_minor = 0;
  int hardware = 0;
  std::string serial;  // 16 bytes as 32 upper-case hex digits
};
inline constexpr std::size_t kInfoBytes = 20;
DeviceInfo DecodeInfo(std::span<const std::uint8_t, kInfoBytes> bytes);

// GET_HEALTH's 3 bytes: 0 good, 1 warning, 2 error (the device needs a reset), and the device's error code.
struct DeviceHealth {
  int status = 0;
  int error_code = 0;
};
inline constexpr std::size_t kHealthBytes = 3;
DeviceHealth DecodeHealth(std::span<const std::uint8_t, kHealthBytes> bytes);

// One measurement of the standard scan: byte 0 the quality (6 bits) over the start flag and its inverse, bytes 1-2
// the angle in 1/64 degree over a check bit that is always 1, bytes 3-4 the distance in 1/4 mm (0: no measurement).
// Its quality is 0..63.
using Node = SweepPoint;
inline constexpr std::size_t kNodeBytes = 5;
std::array<std::uint8_t, kNodeBytes> EncodeNode(const Node& node);
// Nothing when the check bits are wrong (the start flag and its inverse equal, or the check bit 0).
std::optional<Node> DecodeNode(std::span<const std::uint8_t, kNodeBytes> bytes);

// Nodes from a byte stream as the serial port delivers it, in pieces of any size. Where the check bits fail (noise,
// a byte lost) bytes are skipped one at a time until the nodes line up again. A node's check bits leave one chance
// in four that a misaligned one passes, and a byte lost after them goes unseen by them: a node is taken only where it
// turns on clockwise from the one before by a few degrees, as a revolution's measurements do, and after a skip (and
// at first) only where three in a row pass so.
class NodeStream {
 public:
  // Appends the whole nodes `bytes` completes to `out`.
  void Push(std::span<const std::uint8_t> bytes, std::vector<Node>& out);
  std::uint64_t skipped_bytes() const { return skipped_; }
  // Forgets a partial node and the alignment (the port reopened).
  void Clear() {
    pending_.clear();
    in_sync_ = false;
    last_angle_deg_.reset();
  }

 private:
  std::vector<std::uint8_t> pending_;
  bool in_sync_ = false;                  // the nodes line up
  std::optional<double> last_angle_deg_;  // of the last node taken
  std::uint64_t skipped_ = 0;
};

// How the device is asked to scan: SCAN (5-byte nodes, an A1's 2000 samples a second) or the legacy EXPRESS_SCAN
// (working mode 0: capsules of 32 samples, twice as many a second over the same 115200 baud).
enum class ScanMode { kStandard, kExpress };

// EXPRESS_SCAN's request: its payload is the working mode (0) and four reserved bytes.
std::vector<std::uint8_t> EncodeExpressScanRequest();

// One capsule of the express scan: byte 0 holds 0xA over the checksum's low nibble, byte 1 0x5 over its high nibble
// (the checksum: the XOR of bytes 2-83); bytes 2-3 the start angle in 1/64 degree (15 bits) under the start flag S;
// then 16 cabins of 5 bytes, each two samples: a 16-bit little-endian word per sample with its distance in mm in the
// top 14 bits over its angle correction's top two bits, and a fifth byte with the first sample's correction's low
// nibble under the second's. A correction is a 6-bit two's-complement number of 1/8 degree.
inline constexpr std::size_t kCapsuleBytes = 84;
inline constexpr std::size_t kCapsuleSamples = 32;
struct Capsule {
  bool start = false;                                // S: the first capsule since the scan began (or began again)
  double start_angle_deg = 0.0;                      // clockwise from forward: ω, where the capsule's samples begin
  std::array<double, kCapsuleSamples> distance_m{};  // 0: no measurement
  std::array<double, kCapsuleSamples> correction_deg{};  // dθ: the sample's angle is its place between ω's less this
};
std::array<std::uint8_t, kCapsuleBytes> EncodeCapsule(const Capsule& capsule);
// Nothing when the sync nibbles or the checksum are wrong, or the start angle is not below 360 degrees.
std::optional<Capsule> DecodeCapsule(std::span<const std::uint8_t, kCapsuleBytes> bytes);

// The samples of `capsule` appended to `out` given where the next one starts (the document's formula: sample k of 32,
// counted from 0, lies k/32 of the way from its ω to the next, less its correction), clockwise in [0, 360). The
// sample whose place (before the correction) passes forward has the start flag: the document marks a revolution's
// start by the angle falling back, not by S.
void CapsuleSamples(const Capsule& capsule, double next_start_angle_deg, std::vector<SweepPoint>& out);

// Samples from the express scan's byte stream in pieces of any size. A capsule's samples are known once the next
// capsule has come; where bytes are skipped (noise, a capsule that fails its checksum) or a capsule has S set, the
// capsule before is dropped rather than spread over a gap. A capsule is taken where its sync nibbles and checksum
// hold (one misaligned chance in 65536); elsewhere bytes are skipped one at a time.
class CapsuleStream {
 public:
  void Push(std::span<const std::uint8_t> bytes, std::vector<SweepPoint>& out);
  std::uint64_t skipped_bytes() const { return skipped_; }
  std::uint64_t capsules() const { return capsules_; }
  void Clear() {
    pending_.clear();
    previous_.reset();
  }

 private:
  std::vector<std::uint8_t> pending_;
  std::optional<Capsule> previous_;  // the last capsule, whose samples wait for the next one's start angle
  std::uint64_t skipped_ = 0;
  std::uint64_t capsules_ = 0;
};

}  // namespace corridor::drivers::rplidar
