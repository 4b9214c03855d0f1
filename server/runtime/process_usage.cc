#include "server/runtime/process_usage.h"

#include <unistd.h>

#include <fstream>
#include <sstream>
#include <string>

namespace corridor::server {
namespace {

// This process's user and system CPU time, seconds; nullopt when /proc/self/stat cannot be read.
std::optional<double> CpuSeconds() {
  std::ifstream in("/proc/self/stat");
  std::string line;
  if (!std::getline(in, line)) return std::nullopt;
  // The command name, field 2, is in parentheses and may hold spaces: count from after its closing one.
  const std::size_t close = line.rfind(')');
  if (close == std::string::npos) return std::nullopt;
  std::istringstream fields(line.substr(close + 2));
  std::string skip;
  for (int field = 3; field < 14; ++field) fields >> skip;  // state .. cmajflt
  long utime = 0;
  long stime = 0;
  if (!(fields >> utime >> stime)) return std::nullopt;
  return static_cast<double>(utime + stime) / static_cast<double>(::sysconf(_SC_CLK_TCK));
}

// Resident memory, MB; nullopt when /proc/self/statm cannot be read.
std::optional<double> ResidentMb() {
  std::ifstream in("/proc/self/statm");
  long size = 0;
  long resident = 0;
  if (!(in >> size >> resident)) return std::nullopt;
  return static_cast<double>(resident) * static_cast<double>(::sysconf(_SC_PAGESIZE)) / (1024.0 * 1024.0);
}

}  // namespace

std::optional<ProcessUsageSample> ProcessUsage::Sample(drivers::TimeNs now_ns) {
  std::lock_guard lock(mutex_);
  if (window_start_ns_ >= 0 && drivers::ToSeconds(now_ns - window_start_ns_) < kWindowS) return last_;
  const std::optional<double> cpu_s = CpuSeconds();
  const std::optional<double> resident = ResidentMb();
  if (!cpu_s || !resident) return last_;
  if (window_start_ns_ >= 0) {
    const double span_s = drivers::ToSeconds(now_ns - window_start_ns_);
    last_ = ProcessUsageSample{100.0 * (*cpu_s - window_start_cpu_s_) / span_s, *resident};
  }
  window_start_ns_ = now_ns;
  window_start_cpu_s_ = *cpu_s;
  return last_;
}

}  // namespace corridor::server
