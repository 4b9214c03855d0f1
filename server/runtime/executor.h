// Named executors: each is one thread running an Asio io_context. Nodes run on an executor by posting work to it
// (on the arrival of data) or with a PeriodicTimer. The set of executors is declared once, in Executors.
#pragma once

#include <boost/asio/io_context.hpp>
#include <boost/asio/steady_timer.hpp>

#include <chrono>
#include <functional>
#include <memory>
#include <string>
#include <thread>

namespace corridor::server {

class Executor {
 public:
  explicit Executor(std::string name);
  Executor(const Executor&) = delete;
  Executor& operator=(const Executor&) = delete;
  ~Executor();

  const std::string& name() const { return name_; }
  boost::asio::io_context& context() { return context_; }
  // Runs `work` on this executor's thread. Thread-safe.
  void Post(std::function<void()> work);
  void Start();
  // Stops the thread after the handler that is running; pending work is dropped. Idempotent.
  void Stop();

 private:
  std::string name_;
  boost::asio::io_context context_;
  std::unique_ptr<boost::asio::executor_work_guard<boost::asio::io_context::executor_type>> guard_;
  std::thread thread_;
};

// The daemon's executors (ARCHITECTURE.md "The way data flows").
struct Executors {
  Executor control{"control"};        // depth frame -> policy -> safety -> base, and teleop
  Executor mapping{"mapping"};        // localization and maps
  Executor planning{"planning"};      // global plans, on demand
  Executor perception{"perception"};  // detectors
  Executor io{"io"};                  // HTTP, WebSocket, timers of the API
  Executor sim{"sim"};                // the simulator, when enabled

  void StartAll();
  void StopAll();
};

// Calls `tick` every `period` on `executor` until destroyed or stopped; missed ticks are skipped, not bunched.
class PeriodicTimer {
 public:
  PeriodicTimer(Executor& executor, std::chrono::nanoseconds period, std::function<void()> tick);
  PeriodicTimer(const PeriodicTimer&) = delete;
  PeriodicTimer& operator=(const PeriodicTimer&) = delete;
  ~PeriodicTimer();
  // Cancels future ticks. Call from any thread; a tick already running finishes.
  void Stop();

 private:
  struct State;
  std::shared_ptr<State> state_;
};

}  // namespace corridor::server
