// The loop every native driver runs on its thread: a session on its device (open the port, set it up, read until the
// port fails, the device falls silent, or the driver stops), then, unless stopping, a wait of reconnect_s and the next
// session, so that a device plugged back in is taken up again by itself.
#pragma once

#include <functional>
#include <stop_token>
#include <string>

namespace corridor::drivers {

// `session` runs until it returns or throws; what it throws goes to `failed` (its message). `retrying` is called
// before every session after the first. The calling thread is named after `device` (what `top -H` and the CPU
// benchmarks show).
void RunReconnecting(std::stop_token stop, const std::string& device, double reconnect_s,
                     const std::function<void()>& session, const std::function<void(const std::string&)>& failed,
                     const std::function<void()>& retrying);

}  // namespace corridor::drivers
