// Named executors and the timers that run on them, on one Clock.
//
// An executor runs the work posted to it (bus deliveries, replies, timer ticks) one item at a time, in the order
// posted. There are two schedules, chosen once for the whole daemon:
//   - kThreads: each executor is a thread running an Asio io_context; timers wait in real time. corridord on the
//     robot, and with the simulator stepped to keep up with the wall clock.
//   - kLockstep: no threads. The owner advances a simulated clock and calls Executors::RunUntilIdle, which fires the
//     timers that fell due and runs every ready handler, executor by executor in a fixed order, until none is left.
//     The same graph then runs faster than real time and gives the same run for the same inputs (the scenario
//     runner, functional tests).
// Work never takes the daemon down: an exception that escapes a handler is logged with the executor's name and the
// executor goes on with the next item (nodes guard their own handlers first: node.h).
#pragma once

#include <boost/asio/io_context.hpp>

#include <atomic>
#include <chrono>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "drivers/clock.h"

namespace corridor::server {

enum class Schedule { kThreads, kLockstep };

class Executor {
 public:
  // `clock` must outlive the executor; with kThreads it must advance with real time. `urgent`: the control loop's
  // executor, whose subscribers a topic offers each message to before any other's (Topic::Publish).
  Executor(std::string name, const drivers::Clock& clock, Schedule schedule, bool urgent = false);
  Executor(const Executor&) = delete;
  Executor& operator=(const Executor&) = delete;
  ~Executor();

  const std::string& name() const { return name_; }
  const drivers::Clock& clock() const { return clock_; }
  Schedule schedule() const { return schedule_; }
  bool urgent() const { return urgent_; }
  boost::asio::io_context& context() { return context_; }
  // Runs `work` on this executor. Thread-safe.
  void Post(std::function<void()> work);
  // kThreads: starts the thread. kLockstep: nothing (Poll runs the work).
  void Start();
  // Stops the thread after the handler that is running; pending work is dropped. Idempotent.
  void Stop();
  // kLockstep only: fires the timers due on the clock, then runs every ready handler (and what they post), on the
  // caller's thread. Returns how many ran.
  std::size_t Poll();
  // Handlers whose exception reached the executor (a bug in a node that did not guard it): for tests and state.
  std::uint64_t escaped() const { return escaped_.load(); }

 private:
  friend class PeriodicTimer;
  friend class DeadlineTimer;
  struct TimerState;
  void Escaped(const char* what);
  void AddLockstepTimer(std::shared_ptr<TimerState> timer);

  std::string name_;
  const drivers::Clock& clock_;
  Schedule schedule_;
  bool urgent_;
  boost::asio::io_context context_;
  std::unique_ptr<boost::asio::executor_work_guard<boost::asio::io_context::executor_type>> guard_;
  std::thread thread_;
  std::atomic<std::uint64_t> escaped_{0};
  std::mutex timers_mutex_;
  std::vector<std::shared_ptr<TimerState>> lockstep_timers_;  // kLockstep only
};

// The daemon's executors (ARCHITECTURE.md "The way data flows").
class Executors {
 public:
  Executors(const drivers::Clock& clock, Schedule schedule);

  Executor control;     // depth frame -> policy -> safety -> base, and teleop (urgent)
  Executor mapping;     // localization, tracking and maps
  Executor mapping3d;   // the 3D map: its insertions (tens of ms) must not hold localization's scans up
  Executor planning;    // global plans, on demand
  Executor perception;  // detectors and the face
  Executor io;          // HTTP, WebSocket, persistence
  Executor sim;         // the simulator, when enabled
  Executor dds;         // the DDS bridge: ROS 2 messages made and written (maps and images are large)

  Schedule schedule() const { return control.schedule(); }
  void StartAll();
  void StopAll();
  // kLockstep only: polls the executors in a fixed order (sim, control, mapping, mapping3d, planning, perception, io,
  // dds) until none has anything left to run. Returns how many handlers ran.
  std::size_t RunUntilIdle();

 private:
  std::vector<Executor*> all();
};

// Calls `tick` every `period` of the executor's clock on `executor`, from one period after construction until
// destroyed or stopped; missed ticks are skipped, not bunched.
class PeriodicTimer {
 public:
  PeriodicTimer(Executor& executor, std::chrono::nanoseconds period, std::function<void()> tick);
  PeriodicTimer(const PeriodicTimer&) = delete;
  PeriodicTimer& operator=(const PeriodicTimer&) = delete;
  ~PeriodicTimer();
  // Cancels future ticks. Call from any thread; a tick already running finishes.
  void Stop();

 private:
  std::shared_ptr<Executor::TimerState> state_;
};

// Calls `fire` once on `executor` when its clock reaches the time last given to At (a watchdog's deadline, moved on
// whenever what it watches arrives). Not armed until At is called; armed again only by the next At.
class DeadlineTimer {
 public:
  DeadlineTimer(Executor& executor, std::function<void()> fire);
  DeadlineTimer(const DeadlineTimer&) = delete;
  DeadlineTimer& operator=(const DeadlineTimer&) = delete;
  ~DeadlineTimer();
  // Fires at `when_ns` (the executor's clock; at once when it is past) instead of any time set before. Call on the
  // executor.
  void At(drivers::TimeNs when_ns);
  // Disarms it for good. Call from any thread; a firing already running finishes.
  void Stop();

 private:
  std::shared_ptr<Executor::TimerState> state_;
};

}  // namespace corridor::server
