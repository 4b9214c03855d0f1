// What the command-line tools share in reading their options.
#pragma once

#include <charconv>
#include <stdexcept>
#include <string>

namespace corridor::tools {

// `text`, the value of option `flag`, as a number in [lo, hi]; std::invalid_argument naming the option otherwise.
inline double ParseNumber(const std::string& flag, const std::string& text, double lo, double hi) {
  double value = 0.0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc() || end != text.data() + text.size() || !(value >= lo && value <= hi)) {
    throw std::invalid_argument(flag + ": expected a number from " + std::to_string(lo) + " to " + std::to_string(hi) +
                                ", got '" + text + "'");
  }
  return value;
}

}  // namespace corridor::tools
