// What every native driver keeps about its link to its device: its status (a LinkStatus, or a driver's status
// extending it) and the link handler under one mutex, each change of state reported, and the driver's sessions run on
// its thread, opened anew every reconnect_s after one ends or fails (reconnect.h). A driver derives from it, keeps its
// own handlers under the same mutex, and supplies the session.
//
// A session sets its device up on the driver's thread (requests and answers, which may wait), then streams: passes
// over the bytes that came, each handing on what they complete and writing what is due (Stream). The passes run on the
// driver's thread, woken by the device's bytes, until something calls Pump: from then on the pumping thread (the
// daemon's control loop) makes them and the driver's thread sleeps, so that the device's data costs no wake-up of its
// own. Should the pumps stop coming for kPumpWatch (a control loop that hangs), the driver's thread takes the stream
// back: the driver's own watches (the wheels' command timeout, a stale device) hold whoever pumps.
#pragma once

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <mutex>
#include <optional>
#include <span>
#include <stdexcept>
#include <stop_token>
#include <string>
#include <utility>

#include "drivers/clock.h"
#include "drivers/serial/byte_stream.h"
#include "drivers/serial/link_state.h"
#include "drivers/serial/reconnect.h"

namespace corridor::drivers {

// Whether a request asked every period_s is due at `now`, `next_ns` moved on if so. A stream's passes come at their
// own pace (a pump's every control tick), so one within half a period of the due time takes it; on average no more
// often than every period_s.
inline bool Due(TimeNs& next_ns, TimeNs now, double period_s) {
  const TimeNs period = FromSeconds(period_s);
  if (now < next_ns - period / 2) return false;
  next_ns = std::max(next_ns + period, now + period / 2);
  return true;
}

template <typename Status>
class LinkedDevice : public DeviceLink {
 public:
  Status status() const {
    std::lock_guard lock(mutex_);
    return status_;
  }
  LinkStatus link() const override { return status(); }
  void SetLinkHandler(LinkHandler handler) override {
    std::lock_guard lock(mutex_);
    link_handler_ = std::move(handler);
  }
  void Pump() override {
    last_pump_.store(std::chrono::steady_clock::now(), std::memory_order_relaxed);
    std::unique_lock lock(stream_mutex_, std::try_to_lock);  // held: the driver's thread is in a pass of its own
    if (!lock || streaming_ == nullptr || ended_) return;
    try {
      // Until the bytes that came are all taken (a pass takes at most a buffer's worth).
      for (bool more = true; more;) {
        const std::size_t n = streaming_->ReadArrived(buffer_);
        more = n == buffer_.size();
        if (!pass_(std::span<const std::uint8_t>(buffer_.data(), n), false)) ended_ = "";
      }
    } catch (const std::exception& e) {
      ended_ = e.what();
    }
    if (ended_) pumps_ended_.notify_all();
  }

 protected:
  // `device`: the driver's name (its logs, its thread's name); `where`: the port or device it talks to.
  LinkedDevice(std::string device, std::string where) : device_(std::move(device)), where_(std::move(where)) {}

  void SetState(LinkState state, std::string error = {}) {
    ChangeLink(mutex_, status_, link_handler_, device_, where_, state, std::move(error));
  }
  // Runs `session` on the calling thread until `stop`: what it throws is the link disconnected with that error, and
  // every session after the first counts as a reconnect.
  void RunSessions(std::stop_token stop, double reconnect_s, const std::function<void()>& session) {
    RunReconnecting(
        stop, device_, reconnect_s, session,
        [&](const std::string& error) { SetState(LinkState::kDisconnected, error); },
        [&] {
          std::lock_guard lock(mutex_);
          ++status_.reconnects;
        });
  }

  // One pass over the bytes that came (none when a wait ran out); `waited`: they ended a wait on the driver's thread,
  // so came at most their line time before now (a pump's came at any time since the pass before). False ends the
  // session.
  using Pass = std::function<bool(std::span<const std::uint8_t> bytes, bool waited)>;
  // A session's stream, once its device is set up: passes over `stream`'s bytes until one returns false or throws (a
  // pump's exception is thrown here), or `stop`. On this thread each waits up to wait_s() for bytes, unless something
  // pumps (Pump).
  void Stream(ByteStream& stream, std::stop_token stop, const std::function<double()>& wait_s, const Pass& pass) {
    std::unique_lock lock(stream_mutex_);
    streaming_ = &stream;
    pass_ = pass;
    ended_.reset();
    struct Done {
      LinkedDevice& device;
      ~Done() {
        device.streaming_ = nullptr;
        device.pass_ = nullptr;
      }
    } done{*this};
    while (!stop.stop_requested()) {
      if (ended_) {
        if (ended_->empty()) return;
        throw std::runtime_error(*ended_);
      }
      const auto pumped = last_pump_.load(std::memory_order_relaxed);
      if (std::chrono::steady_clock::now() - pumped < kPumpWatch) {
        pumps_ended_.wait_until(lock, stop, pumped + kPumpWatch, [&] { return ended_.has_value(); });
        continue;
      }
      const std::size_t n = stream.Read(buffer_, wait_s());
      if (!pass(std::span<const std::uint8_t>(buffer_.data(), n), n > 0)) return;
    }
  }

  mutable std::mutex mutex_;  // guards status_, the link handler and the driver's own handlers
  Status status_;

 private:
  // Pumps closer together than this keep the driver's thread asleep.
  static constexpr std::chrono::milliseconds kPumpWatch{250};

  std::string device_;
  std::string where_;
  LinkHandler link_handler_;
  std::atomic<std::chrono::steady_clock::time_point> last_pump_{};
  // The stream's passes, whoever makes them (the driver's thread, or a pump when it can take the lock at once):
  std::mutex stream_mutex_;
  std::condition_variable_any pumps_ended_;  // a pump ended the session
  ByteStream* streaming_ = nullptr;          // while a session streams
  Pass pass_;
  std::optional<std::string> ended_;  // a pump ended the session: with what it threw, or empty
  std::array<std::uint8_t, 4096> buffer_{};
};

}  // namespace corridor::drivers
