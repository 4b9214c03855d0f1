// Hokuyo's SCIP 2.0, as "URG Series Communication Protocol Specification SCIP 2.0" documents it, for URG-04LX,
// UTM-30LX and UST-10LX/20LX scanners (USB serial, or TCP on the UST's Ethernet port): a command is a line of ASCII
// ended by LF; the answer repeats it (the echo), then a status line (two characters and a check character: "00P" done,
// "99b" a streamed scan, others errors), then data lines, and an empty line. Every line of the answer after the echo
// ends with a check character: the sum of the line's bytes before it, its low 6 bits, plus 0x30 (parameter lines
// "NAME:value;c" are summed up to the semicolon). Numbers in data are 2, 3 or 4 characters of 6 bits each (the
// character less 0x30), the most significant first; a scan's characters are cut into lines of 64 regardless of where a
// number ends.
//   VV, PP, II    the version, the parameters (model, range limits, steps, scan rate), the state
//   BM / QT       laser on / off (QT also ends a stream)
//   MD            scans streamed: first step, last step, cluster count, scan interval, number of scans (00: for ever),
//                 ranges in mm as 3-character numbers, a time stamp (ms, 4 characters) before each
// Ranges below DMIN are error codes (no echo, too much light, ...), not distances.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace corridor::drivers::hokuyo {

// The check character of `text`.
char CheckCharacter(std::string_view text);
// A number in SCIP's characters (each less 0x30: 6 bits, most significant first); none for a character outside
// 0x30-0x6F.
std::optional<std::uint32_t> DecodeNumber(std::string_view chars);

// "MD" and its parameters: steps first..last, a cluster of `cluster` steps a range, every scan (interval 0), scans
// for ever (0).
std::string EncodeMd(int first_step, int last_step, int cluster = 1, int interval = 0, int scans = 0);

// One answer: its echo and status, and its lines with their check characters checked and removed.
struct Response {
  std::string echo;
  std::string status;  // "00", "99", "0E", ...
  std::vector<std::string> lines;
};

// Answers out of the bytes as they arrive, in pieces. An answer whose status or a line fails its check character is
// dropped whole and counted; bytes before a line that can begin an answer (noise) are skipped.
class ResponseReader {
 public:
  static constexpr std::size_t kMaxLine = 80;  // 64 data characters and a check character, or a parameter line

  void Push(std::span<const std::uint8_t> bytes, std::vector<Response>& out);
  std::uint64_t dropped() const { return dropped_; }

 private:
  void Finish(std::vector<Response>& out);

  std::string line_;
  std::vector<std::string> pending_;  // the lines of the answer under way
  bool overlong_ = false;
  std::uint64_t dropped_ = 0;
};

// The scanner's parameters (PP's answer).
struct Parameters {
  std::string model;
  int min_range_mm = 0;    // DMIN
  int max_range_mm = 0;    // DMAX
  int steps_per_turn = 0;  // ARES
  int first_step = 0;      // AMIN
  int last_step = 0;       // AMAX
  int front_step = 0;      // AFRT: straight ahead
  int scan_rpm = 0;        // SCAN
};
// None when a parameter the driver needs is missing or not a number.
std::optional<Parameters> DecodeParameters(const Response& response);

// A streamed scan (MD's answer "99"): its time stamp and its ranges in mm, one per cluster from the first step.
struct ScanData {
  std::uint32_t timestamp_ms = 0;
  std::vector<std::uint32_t> ranges_mm;
};
// None when it is not a scan, or its characters do not make whole 3-character ranges.
std::optional<ScanData> DecodeScan(const Response& response);

}  // namespace corridor::drivers::hokuyo
