#include "server/runtime/executor.h"

#include <boost/asio/post.hpp>
#include <pthread.h>

#include <atomic>

namespace corridor::server {

Executor::Executor(std::string name) : name_(std::move(name)) {}

Executor::~Executor() { Stop(); }

void Executor::Post(std::function<void()> work) { boost::asio::post(context_, std::move(work)); }

void Executor::Start() {
  if (thread_.joinable()) return;
  guard_ = std::make_unique<boost::asio::executor_work_guard<boost::asio::io_context::executor_type>>(
      context_.get_executor());
  thread_ = std::thread([this] { context_.run(); });
  // Name the thread so that top -H and gdb show which executor is busy (15 characters at most).
  pthread_setname_np(thread_.native_handle(), name_.substr(0, 15).c_str());
}

void Executor::Stop() {
  guard_.reset();
  context_.stop();
  if (thread_.joinable() && thread_.get_id() != std::this_thread::get_id()) thread_.join();
}

void Executors::StartAll() {
  for (Executor* e : {&control, &mapping, &planning, &perception, &io, &sim}) e->Start();
}

void Executors::StopAll() {
  for (Executor* e : {&sim, &perception, &planning, &mapping, &control, &io}) e->Stop();
}

struct PeriodicTimer::State {
  boost::asio::steady_timer timer;
  std::chrono::nanoseconds period;
  std::function<void()> tick;
  std::atomic<bool> stopped{false};
  std::chrono::steady_clock::time_point next;

  State(Executor& e, std::chrono::nanoseconds p, std::function<void()> t)
      : timer(e.context()), period(p), tick(std::move(t)) {}

  static void Arm(const std::shared_ptr<State>& self) {
    self->timer.expires_at(self->next);
    self->timer.async_wait([self](const boost::system::error_code& ec) {
      if (ec || self->stopped) return;
      self->tick();
      const auto now = std::chrono::steady_clock::now();
      self->next += self->period;
      if (self->next < now) self->next = now + self->period;  // fell behind: skip, do not burst
      Arm(self);
    });
  }
};

PeriodicTimer::PeriodicTimer(Executor& executor, std::chrono::nanoseconds period, std::function<void()> tick)
    : state_(std::make_shared<State>(executor, period, std::move(tick))) {
  state_->next = std::chrono::steady_clock::now() + period;
  boost::asio::post(executor.context(), [s = state_] { State::Arm(s); });
}

PeriodicTimer::~PeriodicTimer() { Stop(); }

void PeriodicTimer::Stop() {
  state_->stopped = true;
  boost::asio::post(state_->timer.get_executor(), [s = state_] { s->timer.cancel(); });
}

}  // namespace corridor::server
