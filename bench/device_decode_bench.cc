// What decoding the native devices' data costs (issue 37's target: a driver's decode of a scan or a sensor frame
// timed): an RPLIDAR revolution of 720 standard-scan nodes (or express-scan capsules) through its stream and the
// sweep assembler, and a
// Create 2 sensor frame of the driver's 14 packets through the stream parser, a Kobuki feedback packet (Basic Sensor
// Data, Inertial Sensor, Current) through the packet parser, a TurtleBot 3's state (the OpenCR's 118-byte status
// packet) through the DYNAMIXEL status parser, a serial text base's encoder reply cut into its line and parsed, and a
// Hokuyo UST's scan (1081 ranges in SCIP 2.0's lines) read and decoded. Bytes made with the codecs' encoders or as
// their documents lay them out.
#include <benchmark/benchmark.h>

#include <cmath>
#include <numeric>
#include <vector>

#include "drivers/create2/open_interface.h"
#include "drivers/dynamixel/dynamixel_protocol.h"
#include "drivers/hokuyo/scip_protocol.h"
#include "drivers/kobuki/kobuki_protocol.h"
#include "drivers/lds/lds_protocol.h"
#include "drivers/rplidar/rplidar_protocol.h"
#include "drivers/serial_text/serial_text_protocol.h"
#include "drivers/turtlebot3/opencr_table.h"

namespace corridor::drivers {
namespace {

// Two revolutions of `samples` nodes each, so that the second start flag completes the first: an iteration decodes
// two revolutions' bytes and assembles one scan.
std::vector<std::uint8_t> Revolutions(int samples) {
  std::vector<std::uint8_t> bytes;
  for (int turn = 0; turn < 2; ++turn) {
    for (int i = 0; i < samples; ++i) {
      const auto node = rplidar::EncodeNode({i == 0, 40, 360.0 * i / samples, 1.0 + (i % 50) * 0.1});
      bytes.insert(bytes.end(), node.begin(), node.end());
    }
  }
  return bytes;
}

// Each iteration: `bytes` through a new stream (`Push(bytes, points)`) and a new sweep assembler.
template <typename MakeStream>
void TimeSweeps(benchmark::State& state, const std::vector<std::uint8_t>& bytes, MakeStream make_stream) {
  std::vector<SweepPoint> points;
  for (auto _ : state) {
    auto stream = make_stream();
    SweepAssembler sweeps;
    points.clear();
    stream.Push(bytes, points);
    int scans = 0;
    for (const SweepPoint& p : points) scans += sweeps.Add(p, 0).has_value() ? 1 : 0;
    benchmark::DoNotOptimize(scans);
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * bytes.size()));
}

void BM_RplidarRevolution(benchmark::State& state) {
  const int samples = static_cast<int>(state.range(0));
  const std::vector<std::uint8_t> bytes = Revolutions(samples);
  std::vector<rplidar::Node> nodes;
  for (auto _ : state) {
    rplidar::NodeStream stream;
    SweepAssembler sweeps;
    nodes.clear();
    stream.Push(bytes, nodes);  // a revolution and the next one's start, as pieces of a port's reads would give
    int scans = 0;
    for (const rplidar::Node& n : nodes) scans += sweeps.Add(n, 0).has_value() ? 1 : 0;
    benchmark::DoNotOptimize(scans);
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * bytes.size()));
}
BENCHMARK(BM_RplidarRevolution)->Arg(360)->Arg(720)->Unit(benchmark::kMicrosecond);

// An RPLIDAR A1's express-scan revolution (720 samples at 5.5 Hz): two revolutions of capsules through the capsule
// stream and the sweep assembler, as for the standard scan above.
void BM_RplidarExpressRevolution(benchmark::State& state) {
  constexpr int kSamples = 720;
  std::vector<std::uint8_t> bytes;
  for (int first = 0; first < 2 * kSamples + 64; first += static_cast<int>(rplidar::kCapsuleSamples)) {
    rplidar::Capsule capsule;
    capsule.start = first == 0;
    capsule.start_angle_deg = std::fmod(360.0 * first / kSamples, 360.0);
    for (std::size_t k = 0; k < rplidar::kCapsuleSamples; ++k) {
      capsule.distance_m[k] = 1.0 + static_cast<double>(k % 50) * 0.1;
      capsule.correction_deg[k] = static_cast<double>(k % 5) * 0.25 - 0.5;
    }
    const auto encoded = rplidar::EncodeCapsule(capsule);
    bytes.insert(bytes.end(), encoded.begin(), encoded.end());
  }
  TimeSweeps(state, bytes, [] { return rplidar::CapsuleStream(); });
}
BENCHMARK(BM_RplidarExpressRevolution)->Unit(benchmark::kMicrosecond);

// An LDS-02 revolution: 30 packets of 12 points, each with its CRC, through the packet stream and the sweeps.
void BM_Lds02Revolution(benchmark::State& state) {
  std::vector<std::uint8_t> bytes;
  const auto put16 = [&](unsigned v) {
    bytes.push_back(static_cast<std::uint8_t>(v & 0xFF));
    bytes.push_back(static_cast<std::uint8_t>(v >> 8));
  };
  for (int turn = 0; turn < 2; ++turn) {
    for (unsigned p = 0; p < 30; ++p) {
      const std::size_t begin = bytes.size();
      bytes.insert(bytes.end(), {lds::kLd08Header, lds::kLd08VerLen});
      put16(2160);
      put16(p * 1200);
      for (unsigned i = 0; i < 12; ++i) {
        put16(1000 + 10 * i);
        bytes.push_back(200);
      }
      put16(p * 1200 + 1100);
      put16(p);
      bytes.push_back(lds::Crc8(std::span<const std::uint8_t>(bytes).subspan(begin)));
    }
  }
  TimeSweeps(state, bytes, [] { return lds::PacketStream(lds::Model::kLds02); });
}
BENCHMARK(BM_Lds02Revolution)->Unit(benchmark::kMicrosecond);

void BM_Create2Frame(benchmark::State& state) {
  std::vector<std::uint8_t> body;
  for (const create2::Packet p : create2::StreamedPackets()) {
    body.push_back(static_cast<std::uint8_t>(p));
    for (std::size_t i = 0; i < *create2::PacketSize(static_cast<std::uint8_t>(p)); ++i) body.push_back(0x11);
  }
  std::vector<std::uint8_t> frame = body;
  frame.insert(frame.begin(), {19, static_cast<std::uint8_t>(body.size())});
  const unsigned sum = std::accumulate(frame.begin(), frame.end(), 0u);
  frame.push_back(static_cast<std::uint8_t>((256 - sum % 256) % 256));
  create2::StreamParser parser;
  std::vector<create2::SensorFrame> frames;
  for (auto _ : state) {
    frames.clear();
    parser.Push(frame, frames);
    benchmark::DoNotOptimize(frames.data());
  }
}
BENCHMARK(BM_Create2Frame)->Unit(benchmark::kNanosecond);

void BM_KobukiPacket(benchmark::State& state) {
  std::vector<std::uint8_t> payload{1, 15};
  payload.insert(payload.end(), 15, 0x11);
  payload.insert(payload.end(), {4, 7, 0x28, 0x23, 0, 0, 0, 0, 0, 6, 2, 12, 12});
  const std::vector<std::uint8_t> packet = kobuki::EncodePacket(payload);
  kobuki::PacketParser parser;
  std::vector<kobuki::FeedbackPacket> packets;
  for (auto _ : state) {
    packets.clear();
    parser.Push(packet, packets);
    benchmark::DoNotOptimize(packets.data());
  }
}
BENCHMARK(BM_KobukiPacket)->Unit(benchmark::kNanosecond);

void BM_TurtleBot3State(benchmark::State& state) {
  // The board's answer to the driver's Read: a status packet of kStateLength bytes, framed as the board frames it.
  std::vector<std::uint8_t> packet{0xFF, 0xFF, 0xFD, 0x00, turtlebot3::kOpenCrId};
  const std::size_t length = turtlebot3::kStateLength + 4;
  packet.insert(packet.end(),
                {static_cast<std::uint8_t>(length & 0xFF), static_cast<std::uint8_t>(length >> 8), 0x55, 0});
  for (int i = 0; i < turtlebot3::kStateLength; ++i) packet.push_back(static_cast<std::uint8_t>(i * 7));
  const std::uint16_t crc = dynamixel::Crc16(packet);
  packet.push_back(crc & 0xFF);
  packet.push_back(crc >> 8);
  dynamixel::StatusParser parser;
  std::vector<dynamixel::StatusPacket> packets;
  for (auto _ : state) {
    packets.clear();
    parser.Push(packet, packets);
    benchmark::DoNotOptimize(packets.data());
  }
}
BENCHMARK(BM_TurtleBot3State)->Unit(benchmark::kNanosecond);

void BM_SerialTextReply(benchmark::State& state) {
  const std::string reply = "-2147480647 2147480647\r\n";
  const std::span<const std::uint8_t> bytes(reinterpret_cast<const std::uint8_t*>(reply.data()), reply.size());
  serial_text::LineSplitter lines;
  std::vector<std::string> got;
  for (auto _ : state) {
    got.clear();
    lines.Push(bytes, got);
    benchmark::DoNotOptimize(serial_text::ParseEncoders(got.front()));
  }
}
BENCHMARK(BM_SerialTextReply)->Unit(benchmark::kNanosecond);

void BM_HokuyoScan(benchmark::State& state) {
  // A UST-10LX's scan as SCIP 2.0 streams it: echo, status, time stamp, 1081 3-character ranges in lines of 64.
  const auto line = [](const std::string& body) { return body + hokuyo::CheckCharacter(body) + "\n"; };
  std::string data;
  for (int i = 0; i < 1081; ++i) {
    const int mm = 500 + (i * 37) % 20000;
    data += {static_cast<char>(((mm >> 12) & 0x3F) + 0x30), static_cast<char>(((mm >> 6) & 0x3F) + 0x30),
             static_cast<char>((mm & 0x3F) + 0x30)};
  }
  std::string text = "MD0000108001000\n99b\n" + line("0000");
  for (std::size_t at = 0; at < data.size(); at += 64) text += line(data.substr(at, 64));
  text += "\n";
  const std::span<const std::uint8_t> bytes(reinterpret_cast<const std::uint8_t*>(text.data()), text.size());
  hokuyo::ResponseReader reader;
  std::vector<hokuyo::Response> answers;
  for (auto _ : state) {
    answers.clear();
    reader.Push(bytes, answers);
    benchmark::DoNotOptimize(hokuyo::DecodeScan(answers.front()));
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * text.size()));
}
BENCHMARK(BM_HokuyoScan)->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace corridor::drivers

BENCHMARK_MAIN();
