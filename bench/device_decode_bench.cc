// What decoding the native devices' data costs (issue 37's target: a driver's decode of a scan or a sensor frame
// timed): an RPLIDAR revolution of 720 standard-scan nodes through the node stream and the sweep assembler, and a
// Create 2 sensor frame of the driver's 14 packets through the stream parser, and a Kobuki feedback packet (Basic
// Sensor Data, Inertial Sensor, Current) through the packet parser. Bytes made with the codecs' encoders.
#include <benchmark/benchmark.h>

#include <numeric>
#include <vector>

#include "drivers/create2/open_interface.h"
#include "drivers/kobuki/kobuki_protocol.h"
#include "drivers/rplidar/rplidar_protocol.h"

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

void BM_RplidarRevolution(benchmark::State& state) {
  const int samples = static_cast<int>(state.range(0));
  const std::vector<std::uint8_t> bytes = Revolutions(samples);
  std::vector<rplidar::Node> nodes;
  for (auto _ : state) {
    rplidar::NodeStream stream;
    rplidar::SweepAssembler sweeps;
    nodes.clear();
    stream.Push(bytes, nodes);  // a revolution and the next one's start, as pieces of a port's reads would give
    int scans = 0;
    for (const rplidar::Node& n : nodes) scans += sweeps.Add(n, 0).has_value() ? 1 : 0;
    benchmark::DoNotOptimize(scans);
  }
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations() * bytes.size()));
}
BENCHMARK(BM_RplidarRevolution)->Arg(360)->Arg(720)->Unit(benchmark::kMicrosecond);

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

}  // namespace
}  // namespace corridor::drivers

BENCHMARK_MAIN();
