#include "drivers/serial_text/serial_text_protocol.h"

#include <charconv>

#include <spdlog/fmt/fmt.h>

namespace corridor::drivers::serial_text {
namespace {

// A whole signed decimal number, nothing before or after it.
std::optional<std::int32_t> ParseCount(std::string_view text) {
  std::int32_t value = 0;
  const char* end = text.data() + text.size();
  const auto [at, error] = std::from_chars(text.data(), end, value);
  if (text.empty() || error != std::errc{} || at != end) return std::nullopt;
  return value;
}

}  // namespace

int LineSplitter::Push(std::span<const std::uint8_t> bytes, std::vector<std::string>& lines) {
  int overlong = 0;
  for (const std::uint8_t b : bytes) {
    const char c = static_cast<char>(b);
    if (c == '\n') {
      if (!skipping_) {
        if (!partial_.empty() && partial_.back() == '\r') partial_.pop_back();
        lines.push_back(std::move(partial_));
      }
      partial_.clear();
      skipping_ = false;
    } else if (!skipping_) {
      partial_.push_back(c);
      if (partial_.size() > kMaxLine) {
        ++overlong;
        partial_.clear();
        skipping_ = true;
      }
    }
  }
  return overlong;
}

std::optional<EncoderCounts> ParseEncoders(std::string_view line) {
  const std::size_t space = line.find(' ');
  if (space == std::string_view::npos) return std::nullopt;
  const std::optional<std::int32_t> left = ParseCount(line.substr(0, space));
  const std::optional<std::int32_t> right = ParseCount(line.substr(space + 1));
  if (!left || !right) return std::nullopt;
  return EncoderCounts{*left, *right};
}

std::int64_t CountsChange(std::int32_t before, std::int32_t now) {
  return static_cast<std::int32_t>(static_cast<std::uint32_t>(now) - static_cast<std::uint32_t>(before));
}

std::string EncodeMotorSpeeds(int left_counts_per_frame, int right_counts_per_frame) {
  return fmt::format("m {} {}\r", left_counts_per_frame, right_counts_per_frame);
}

}  // namespace corridor::drivers::serial_text
