#include "testing/emulators/hokuyo_emulator.h"

#include <chrono>
#include <cmath>
#include <numbers>

#include "testing/emulators/device_end.h"
#include "testing/emulators/pseudo_terminal.h"
#include "testing/emulators/tcp_endpoint.h"

namespace corridor::testing {
namespace {

// The document's check character: the low 6 bits of the sum, plus 0x30.
char Check(const std::string& text) {
  unsigned sum = 0;
  for (const char c : text) sum += static_cast<unsigned char>(c);
  return static_cast<char>((sum & 0x3F) + 0x30);
}

// A number in `width` characters of 6 bits, the most significant first, each plus 0x30.
std::string Characters(std::uint32_t value, int width) {
  std::string out(static_cast<std::size_t>(width), '0');
  for (int i = width - 1; i >= 0; --i, value >>= 6)
    out[static_cast<std::size_t>(i)] = static_cast<char>((value & 0x3F) + 0x30);
  return out;
}

}  // namespace

HokuyoModel Urg04lx() { return {"URG-04LX(Hokuyo Automatic Co.,Ltd.)", 20, 5600, 1024, 44, 725, 384, 600}; }
HokuyoModel Ust10lx() { return {"UST-10LX(Hokuyo Automatic Co.,Ltd.)", 20, 30000, 1440, 0, 1080, 540, 2400}; }

HokuyoEmulator::HokuyoEmulator(std::filesystem::path link, HokuyoEmulatorOptions options)
    : options_(std::move(options)), end_(std::make_unique<PseudoTerminal>(std::move(link))) {
  Start();
}

HokuyoEmulator::HokuyoEmulator(HokuyoEmulatorOptions options) : options_(std::move(options)) {
  auto tcp = std::make_unique<TcpEndpoint>();
  port_ = tcp->port();
  end_ = std::move(tcp);
  Start();
}

void HokuyoEmulator::Start() {
  start_s_ = NowS();
  thread_ = std::jthread([this](std::stop_token stop) { Serve(stop); });
}

HokuyoEmulator::~HokuyoEmulator() {
  thread_.request_stop();
  if (thread_.joinable()) thread_.join();
}

int HokuyoEmulator::scans_sent() const {
  std::lock_guard lock(mutex_);
  return scans_sent_;
}
bool HokuyoEmulator::laser_on() const {
  std::lock_guard lock(mutex_);
  return laser_on_;
}
void HokuyoEmulator::Noise(std::string bytes) {
  std::lock_guard lock(mutex_);
  noise_ = std::move(bytes);
}
void HokuyoEmulator::BadCheck() {
  std::lock_guard lock(mutex_);
  bad_check_ = true;
}
void HokuyoEmulator::DropByte() {
  std::lock_guard lock(mutex_);
  drop_byte_ = true;
}
void HokuyoEmulator::Silence() {
  std::lock_guard lock(mutex_);
  silent_ = true;
}
void HokuyoEmulator::Resume() {
  std::lock_guard lock(mutex_);
  silent_ = false;
}
void HokuyoEmulator::Unplug() {
  std::lock_guard lock(mutex_);
  end_->Unplug();
}
void HokuyoEmulator::Replug() {
  std::lock_guard lock(mutex_);
  end_->Plug();
  received_.clear();
  laser_on_ = streaming_ = false;
}

void HokuyoEmulator::Answer(const std::string& echo, const std::string& status, const std::vector<std::string>& lines) {
  std::string text = echo + "\n" + status + Check(status) + "\n";
  for (const std::string& line : lines) text += line + "\n";
  text += "\n";
  end_->Send(std::span(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()));
}

void HokuyoEmulator::Handle(const std::string& command) {
  const HokuyoModel& m = options_.model;
  // Parameter lines: "NAME:value;" and the check character of what precedes the semicolon.
  const auto parameter = [](const std::string& name, const std::string& value) {
    const std::string body = name + ":" + value;
    return body + ";" + Check(body);
  };
  if (command == "SCIP2.0") {
    Answer(command, "00");
  } else if (command == "VV") {
    Answer(command, "00",
           {parameter("VEND", "Hokuyo Automatic Co.,Ltd."), parameter("PROD", m.name), parameter("FIRM", "1.0.0"),
            parameter("PROT", "SCIP 2.0"), parameter("SERI", "H0000001")});
  } else if (command == "PP") {
    Answer(command, "00",
           {parameter("MODL", m.name), parameter("DMIN", std::to_string(m.dmin_mm)),
            parameter("DMAX", std::to_string(m.dmax_mm)), parameter("ARES", std::to_string(m.ares)),
            parameter("AMIN", std::to_string(m.amin)), parameter("AMAX", std::to_string(m.amax)),
            parameter("AFRT", std::to_string(m.afrt)), parameter("SCAN", std::to_string(m.scan_rpm))});
  } else if (command == "II") {
    Answer(command, "00",
           {parameter("MODL", m.name), parameter("LASR", laser_on_ ? "ON" : "OFF"),
            parameter("SCSP", std::to_string(m.scan_rpm)), parameter("MESM", "Measuring")});
  } else if (command == "BM") {
    Answer(command, laser_on_ ? "02" : "00");  // 02: the laser was on already
    laser_on_ = true;
  } else if (command == "QT") {
    Answer(command, "00");
    laser_on_ = streaming_ = false;
  } else if (command == "RS") {
    Answer(command, "00");
    laser_on_ = streaming_ = false;
  } else if (command.size() == 15 && command.starts_with("MD")) {
    const auto number = [&](std::size_t at, std::size_t n) { return std::atoi(command.substr(at, n).c_str()); };
    const int first = number(2, 4), last = number(6, 4), cluster = number(10, 2);
    if (first < m.amin || last > m.amax || first > last || cluster < 1) {
      Answer(command, "04");  // a step out of range
      return;
    }
    md_first_ = first;
    md_last_ = last;
    md_cluster_ = cluster;
    md_echo_ = command;
    laser_on_ = streaming_ = true;  // MD turns the laser on
    Answer(command, "00");
    next_scan_s_ = NowS();
  } else {
    Answer(command, "0E");  // not a command this emulator knows
  }
}

std::string HokuyoEmulator::Scan(double now_s) {
  const HokuyoModel& m = options_.model;
  std::string data;
  for (int step = md_first_; step <= md_last_; step += md_cluster_) {
    const double angle = (step - m.afrt) * 2.0 * std::numbers::pi / m.ares;
    const double metres = options_.range(angle);
    const std::uint32_t mm = metres > 0.0 ? static_cast<std::uint32_t>(std::lround(metres * 1000.0)) : 1;
    data += Characters(std::min<std::uint32_t>(mm, static_cast<std::uint32_t>(m.dmax_mm)), 3);
  }
  const std::string stamp = Characters(static_cast<std::uint32_t>((now_s - start_s_) * 1000.0) & 0xFFFFFF, 4);
  std::string text = md_echo_ + "\n99b\n" + stamp + Check(stamp) + "\n";
  for (std::size_t at = 0; at < data.size(); at += 64) {
    const std::string line = data.substr(at, 64);
    char check = Check(line);
    if (bad_check_) {
      check = check == '0' ? '1' : '0';
      bad_check_ = false;
    }
    text += line + check + "\n";
  }
  text += "\n";
  if (drop_byte_) {
    text.erase(text.size() / 2, 1);
    drop_byte_ = false;
  }
  return noise_ + text;
}

void HokuyoEmulator::Step(double now_s) {
  std::vector<std::uint8_t> bytes;
  end_->Receive(bytes, 0);
  if (!silent_) received_.append(bytes.begin(), bytes.end());
  for (std::size_t end; (end = received_.find('\n')) != std::string::npos;) {
    std::string command = received_.substr(0, end);
    received_.erase(0, end + 1);
    if (!command.empty() && command.back() == '\r') command.pop_back();  // CR LF is taken as LF
    if (!command.empty()) Handle(command);
  }
  if (!streaming_ || silent_ || now_s < next_scan_s_) return;
  next_scan_s_ += 60.0 / options_.model.scan_rpm;
  if (next_scan_s_ < now_s) next_scan_s_ = now_s;  // fell behind: no burst of old scans
  const std::string text = Scan(now_s);
  noise_.clear();
  end_->Send(std::span(reinterpret_cast<const std::uint8_t*>(text.data()), text.size()));
  ++scans_sent_;
}

void HokuyoEmulator::Serve(std::stop_token stop) {
  while (!stop.stop_requested()) {
    {
      std::lock_guard lock(mutex_);
      Step(NowS());
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(1));  // the device's pace; the faults' lock free meanwhile
  }
}

}  // namespace corridor::testing
