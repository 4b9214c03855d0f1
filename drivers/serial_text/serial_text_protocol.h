// The plain serial text protocol of home-made Arduino-class bases, as the ROSArduinoBridge firmware documents it (its
// README's command list): a command is a letter and its arguments, separated by spaces and ended by a carriage
// return; the board answers each with a line ended by CR LF.
//   e        the encoders' counts: "<left> <right>" (signed 32-bit counts)
//   m L R    the wheels' speeds, in encoder counts per PID frame (PID_RATE, 30 a second by default): "OK"
//   r        the counts set to zero: "OK"
//   b        the baud rate: "57600"
// An unknown command is answered "Invalid Command". The board stops its wheels by itself when no `m` came for 2 s
// (AUTO_STOP_INTERVAL), and restarts when its port is opened (the DTR line resets an Arduino).
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace corridor::drivers::serial_text {

inline constexpr std::string_view kReadEncoders = "e\r";

// What the board sends, cut into lines at LF (a CR before it dropped). A line longer than any the protocol has is
// garbage (noise, a baud rate that does not match): dropped.
class LineSplitter {
 public:
  static constexpr std::size_t kMaxLine = 40;  // two signed 32-bit counts and a space take 23

  // Appends the lines `bytes` complete; returns how many too long were dropped.
  int Push(std::span<const std::uint8_t> bytes, std::vector<std::string>& lines);

 private:
  std::string partial_;
  bool skipping_ = false;  // inside a line already found too long
};

struct EncoderCounts {
  std::int32_t left = 0;
  std::int32_t right = 0;
};

// "1234 -56": the two counts. Anything else (OK, Invalid Command, a number alone, a count out of 32 bits, stray
// characters): none.
std::optional<EncoderCounts> ParseEncoders(std::string_view line);
// The change from `before` to `now` of a 32-bit count that wraps either way.
std::int64_t CountsChange(std::int32_t before, std::int32_t now);
// "m <left> <right>\r".
std::string EncodeMotorSpeeds(int left_counts_per_frame, int right_counts_per_frame);

}  // namespace corridor::drivers::serial_text
