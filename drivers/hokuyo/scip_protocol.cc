#include "drivers/hokuyo/scip_protocol.h"

#include <charconv>

#include <spdlog/fmt/fmt.h>

namespace corridor::drivers::hokuyo {
namespace {

// Whether `echo` is a command whose data lines are "NAME:value;c".
bool ParameterLines(std::string_view echo) {
  return echo.starts_with("PP") || echo.starts_with("VV") || echo.starts_with("II");
}

// `line` without its check character (and the semicolon before it, for a parameter line); none if it fails.
std::optional<std::string> Checked(const std::string& line, bool parameter) {
  const std::size_t cut = parameter ? 2 : 1;
  if (line.size() <= cut || (parameter && line[line.size() - 2] != ';')) return std::nullopt;
  const std::string_view body(line.data(), line.size() - cut);
  if (CheckCharacter(body) != line.back()) return std::nullopt;
  return std::string(body);
}

std::optional<int> Integer(std::string_view text) {
  int value = 0;
  const auto [at, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (text.empty() || error != std::errc{} || at != text.data() + text.size()) return std::nullopt;
  return value;
}

}  // namespace

char CheckCharacter(std::string_view text) {
  unsigned sum = 0;
  for (const char c : text) sum += static_cast<unsigned char>(c);
  return static_cast<char>((sum & 0x3F) + 0x30);
}

std::optional<std::uint32_t> DecodeNumber(std::string_view chars) {
  std::uint32_t value = 0;
  for (const char c : chars) {
    if (c < 0x30 || c > 0x6F) return std::nullopt;
    value = (value << 6) | static_cast<std::uint32_t>(c - 0x30);
  }
  return value;
}

std::string EncodeMd(int first_step, int last_step, int cluster, int interval, int scans) {
  return fmt::format("MD{:04d}{:04d}{:02d}{:01d}{:02d}\n", first_step, last_step, cluster, interval, scans);
}

void ResponseReader::Push(std::span<const std::uint8_t> bytes, std::vector<Response>& out) {
  for (const std::uint8_t b : bytes) {
    const char c = static_cast<char>(b);
    if (c != '\n') {
      if (line_.size() < kMaxLine) {
        line_.push_back(c);
      } else {
        overlong_ = true;  // garbage, or two answers run together: this answer is lost
      }
      continue;
    }
    if (!line_.empty()) {
      pending_.push_back(std::move(line_));
      line_.clear();
    } else if (!pending_.empty()) {
      Finish(out);  // the empty line ends the answer
    }
  }
}

void ResponseReader::Finish(std::vector<Response>& out) {
  const std::vector<std::string> lines = std::move(pending_);
  pending_.clear();
  const bool overlong = overlong_;
  overlong_ = false;
  if (overlong || lines.size() < 2) {
    ++dropped_;
    return;
  }
  Response response;
  response.echo = lines[0];
  const std::optional<std::string> status = Checked(lines[1], false);
  if (!status || status->size() != 2) {
    ++dropped_;
    return;
  }
  response.status = *status;
  const bool parameter = ParameterLines(response.echo);
  for (std::size_t i = 2; i < lines.size(); ++i) {
    std::optional<std::string> line = Checked(lines[i], parameter);
    if (!line) {
      ++dropped_;
      return;
    }
    response.lines.push_back(std::move(*line));
  }
  out.push_back(std::move(response));
}

std::optional<Parameters> DecodeParameters(const Response& response) {
  if (response.status != "00") return std::nullopt;
  Parameters p;
  int found = 0;
  for (const std::string& line : response.lines) {
    const std::size_t colon = line.find(':');
    if (colon == std::string::npos) continue;
    const std::string_view name(line.data(), colon);
    const std::string_view value(line.data() + colon + 1, line.size() - colon - 1);
    if (name == "MODL") {
      p.model = std::string(value);
      continue;
    }
    int* field = name == "DMIN"   ? &p.min_range_mm
                 : name == "DMAX" ? &p.max_range_mm
                 : name == "ARES" ? &p.steps_per_turn
                 : name == "AMIN" ? &p.first_step
                 : name == "AMAX" ? &p.last_step
                 : name == "AFRT" ? &p.front_step
                 : name == "SCAN" ? &p.scan_rpm
                                  : nullptr;
    if (!field) continue;
    const std::optional<int> number = Integer(value);
    if (!number) return std::nullopt;
    *field = *number;
    ++found;
  }
  if (found != 7 || p.steps_per_turn <= 0 || p.first_step > p.last_step || p.max_range_mm <= p.min_range_mm) {
    return std::nullopt;
  }
  return p;
}

std::optional<ScanData> DecodeScan(const Response& response) {
  if (response.status != "99" || response.lines.empty() || response.lines[0].size() != 4) return std::nullopt;
  ScanData scan;
  const std::optional<std::uint32_t> stamp = DecodeNumber(response.lines[0]);
  if (!stamp) return std::nullopt;
  scan.timestamp_ms = *stamp;
  std::string chars;
  for (std::size_t i = 1; i < response.lines.size(); ++i) chars += response.lines[i];
  if (chars.size() % 3 != 0) return std::nullopt;
  scan.ranges_mm.reserve(chars.size() / 3);
  for (std::size_t at = 0; at < chars.size(); at += 3) {
    const std::optional<std::uint32_t> range = DecodeNumber(std::string_view(chars).substr(at, 3));
    if (!range) return std::nullopt;
    scan.ranges_mm.push_back(*range);
  }
  return scan;
}

}  // namespace corridor::drivers::hokuyo
