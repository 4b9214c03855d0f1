// libFuzzer target: the native devices' byte streams, which come from whatever is plugged into the robot (noise, a
// device at another baud rate, a different firmware), through each protocol's parser as the drivers feed it, in
// pieces of any size: the RPLIDAR's nodes, capsules and sweeps, the Create 2's stream, the Kobuki's packets, DYNAMIXEL
// status packets (TurtleBot 3), SCIP answers and scans (Hokuyo), the LDS-01/02 packets (TurtleBot 3's lasers), and the
// serial text protocol's lines. Nothing may crash, read out of bounds, or grow without bound; what a parser hands on
// must be whole.
#include <fuzzer/FuzzedDataProvider.h>

#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <vector>

#include "drivers/create2/open_interface.h"
#include "drivers/dynamixel/dynamixel_protocol.h"
#include "drivers/hokuyo/scip_protocol.h"
#include "drivers/kobuki/kobuki_protocol.h"
#include "drivers/lds/lds_protocol.h"
#include "drivers/rplidar/rplidar_protocol.h"
#include "drivers/serial_text/serial_text_protocol.h"

namespace {

using namespace corridor::drivers;

// The rest of the input, in reads of 1 to 300 bytes as a port would give them.
template <typename Feed>
void InPieces(FuzzedDataProvider& input, Feed feed) {
  while (input.remaining_bytes() > 0) {
    const std::size_t n = input.ConsumeIntegralInRange<std::size_t>(1, 300);
    const std::vector<std::uint8_t> piece = input.ConsumeBytes<std::uint8_t>(n);
    feed(std::span<const std::uint8_t>(piece));
  }
}

void Check(bool holds) {
  if (!holds) std::abort();
}

// The rest of the input through a rotating laser's stream (`Push(bytes, points)`) and the sweep assembler: every
// point forward of 360 degrees, every scan whole.
template <typename Stream>
void Sweeps(FuzzedDataProvider& input, Stream& stream) {
  SweepAssembler sweeps;
  std::vector<SweepPoint> points;
  InPieces(input, [&](std::span<const std::uint8_t> bytes) {
    points.clear();
    stream.Push(bytes, points);
    for (const SweepPoint& point : points) {
      Check(point.angle_deg >= 0.0 && point.angle_deg < 360.0);
      if (const auto scan = sweeps.Add(point, 0)) Check(scan->ranges.size() == 360);
    }
  });
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  FuzzedDataProvider input(data, size);
  switch (input.ConsumeIntegralInRange<int>(0, 7)) {
    case 0: {
      rplidar::NodeStream stream;
      SweepAssembler sweeps;
      std::vector<rplidar::Node> nodes;
      InPieces(input, [&](std::span<const std::uint8_t> bytes) {
        nodes.clear();
        stream.Push(bytes, nodes);
        for (const rplidar::Node& node : nodes) {
          if (const auto scan = sweeps.Add(node, 0)) Check(scan->ranges.size() == 360);
        }
      });
      break;
    }
    case 1: {
      create2::StreamParser parser;
      std::vector<create2::SensorFrame> frames;
      InPieces(input, [&](std::span<const std::uint8_t> bytes) { parser.Push(bytes, frames); });
      break;
    }
    case 2: {
      kobuki::PacketParser parser;
      std::vector<kobuki::FeedbackPacket> packets;
      InPieces(input, [&](std::span<const std::uint8_t> bytes) { parser.Push(bytes, packets); });
      break;
    }
    case 3: {
      dynamixel::StatusParser parser;
      std::vector<dynamixel::StatusPacket> packets;
      InPieces(input, [&](std::span<const std::uint8_t> bytes) { parser.Push(bytes, packets); });
      for (const dynamixel::StatusPacket& p : packets) Check(p.parameters.size() <= 1024);
      break;
    }
    case 4: {
      hokuyo::ResponseReader reader;
      std::vector<hokuyo::Response> answers;
      InPieces(input, [&](std::span<const std::uint8_t> bytes) { reader.Push(bytes, answers); });
      for (const hokuyo::Response& answer : answers) {
        for (const std::string& line : answer.lines) Check(line.size() < hokuyo::ResponseReader::kMaxLine);
        hokuyo::DecodeScan(answer);
        hokuyo::DecodeParameters(answer);
      }
      break;
    }
    case 6: {
      rplidar::CapsuleStream stream;
      Sweeps(input, stream);
      break;
    }
    case 5: {
      lds::PacketStream stream(input.ConsumeBool() ? lds::Model::kLds01 : lds::Model::kLds02);
      Sweeps(input, stream);
      break;
    }
    default: {
      serial_text::LineSplitter lines;
      std::vector<std::string> got;
      InPieces(input, [&](std::span<const std::uint8_t> bytes) { lines.Push(bytes, got); });
      for (const std::string& line : got) {
        Check(line.size() <= serial_text::LineSplitter::kMaxLine);
        serial_text::ParseEncoders(line);
      }
    }
  }
  return 0;
}
