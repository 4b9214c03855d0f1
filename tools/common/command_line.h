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

// A command line's arguments from `first` on, one at a time: Next() moves to the next (false after the last), Value()
// takes the one after it as the current option's value (std::invalid_argument naming the option when there is none).
class Arguments {
 public:
  Arguments(int argc, char** argv, int first = 1) : argc_(argc), argv_(argv), next_(first) {}
  bool Next() {
    if (next_ >= argc_) return false;
    current_ = argv_[next_++];
    return true;
  }
  const std::string& current() const { return current_; }
  std::string Value() {
    if (next_ >= argc_) throw std::invalid_argument(current_ + ": needs a value");
    return argv_[next_++];
  }

 private:
  int argc_;
  char** argv_;
  int next_;
  std::string current_;
};

}  // namespace corridor::tools
