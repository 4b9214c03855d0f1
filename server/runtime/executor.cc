#include "server/runtime/executor.h"

#include <boost/asio/post.hpp>
#include <boost/asio/steady_timer.hpp>
#include <pthread.h>
#include <spdlog/spdlog.h>

#include <limits>
#include <optional>

#include "nav/demand.h"

namespace corridor::server {

struct Executor::TimerState {
  static constexpr drivers::TimeNs kUnarmed = std::numeric_limits<drivers::TimeNs>::max();

  Executor& executor;
  drivers::TimeNs period_ns;  // 0: once (a DeadlineTimer), then unarmed until set again
  std::function<void()> tick;
  std::atomic<bool> stopped{false};
  drivers::TimeNs next_ns = 0;                     // on the executor's clock
  std::optional<boost::asio::steady_timer> timer;  // kThreads

  TimerState(Executor& e, drivers::TimeNs period, std::function<void()> t)
      : executor(e), period_ns(period), tick(std::move(t)), next_ns(e.clock().Now() + period) {}

  // One tick, guarded; the next is one period on, or one period from now when it fell behind.
  void Fire(drivers::TimeNs now) {
    try {
      tick();
    } catch (const std::exception& e) {
      executor.Escaped(e.what());
    } catch (...) {
      executor.Escaped("an exception that is not a std::exception");
    }
    if (period_ns == 0) {
      next_ns = kUnarmed;
      return;
    }
    next_ns += period_ns;
    if (next_ns <= now) next_ns = now + period_ns;
  }

  // kThreads: waits in real time for the clock to reach next_ns. A wait that ends early (the clock and the steady
  // clock differ, or a deadline moved later after its wait had ended) waits again.
  static void Arm(const std::shared_ptr<TimerState>& self) {
    if (self->next_ns == kUnarmed) return;
    const drivers::TimeNs wait = std::max<drivers::TimeNs>(0, self->next_ns - self->executor.clock().Now());
    self->timer->expires_after(std::chrono::nanoseconds(wait));
    self->timer->async_wait([self](const boost::system::error_code& ec) {
      if (ec || self->stopped) return;
      const drivers::TimeNs now = self->executor.clock().Now();
      if (now >= self->next_ns) self->Fire(now);
      Arm(self);
    });
  }
};

Executor::Executor(std::string name, const drivers::Clock& clock, Schedule schedule, bool urgent)
    : name_(std::move(name)), clock_(clock), schedule_(schedule), urgent_(urgent) {}

Executor::~Executor() { Stop(); }

void Executor::Escaped(const char* what) {
  ++escaped_;
  spdlog::error("executor {}: a handler failed and was dropped: {}", name_, what);
}

void Executor::Post(std::function<void()> work) {
  boost::asio::post(context_, [this, work = std::move(work)] {
    try {
      work();
    } catch (const std::exception& e) {
      Escaped(e.what());
    } catch (...) {
      Escaped("an exception that is not a std::exception");
    }
  });
}

void Executor::Start() {
  if (schedule_ == Schedule::kLockstep || thread_.joinable()) return;
  guard_ = std::make_unique<boost::asio::executor_work_guard<boost::asio::io_context::executor_type>>(
      context_.get_executor());
  thread_ = std::thread([this] {
    // Asio's own handlers (sockets, timers) may throw too; the executor logs it and runs on.
    while (true) {
      try {
        context_.run();
        return;
      } catch (const std::exception& e) {
        Escaped(e.what());
      } catch (...) {
        Escaped("an exception that is not a std::exception");
      }
    }
  });
  // Name the thread so that top -H and gdb show which executor is busy (15 characters at most).
  pthread_setname_np(thread_.native_handle(), name_.substr(0, 15).c_str());
}

void Executor::Stop() {
  guard_.reset();
  context_.stop();
  if (thread_.joinable() && thread_.get_id() != std::this_thread::get_id()) thread_.join();
}

void Executor::AddLockstepTimer(std::shared_ptr<TimerState> timer) {
  std::lock_guard lock(timers_mutex_);
  lockstep_timers_.push_back(std::move(timer));
}

std::size_t Executor::Poll() {
  DEMAND(schedule_ == Schedule::kLockstep);
  std::size_t ran = 0;
  const drivers::TimeNs now = clock_.Now();
  std::vector<std::shared_ptr<TimerState>> due;
  {
    std::lock_guard lock(timers_mutex_);
    std::erase_if(lockstep_timers_, [](const auto& t) { return t->stopped.load(); });
    for (const auto& t : lockstep_timers_) {
      if (t->next_ns <= now) due.push_back(t);
    }
  }
  for (const auto& t : due) {
    if (t->stopped) continue;
    t->Fire(now);
    ++ran;
  }
  context_.restart();
  while (true) {
    try {
      ran += context_.poll();
      return ran;
    } catch (const std::exception& e) {
      Escaped(e.what());
    } catch (...) {
      Escaped("an exception that is not a std::exception");
    }
  }
}

Executors::Executors(const drivers::Clock& clock, Schedule schedule)
    : control("control", clock, schedule, true),
      mapping("mapping", clock, schedule),
      mapping3d("mapping3d", clock, schedule),
      planning("planning", clock, schedule),
      perception("perception", clock, schedule),
      io("io", clock, schedule),
      sim("sim", clock, schedule),
      dds("dds", clock, schedule) {}

std::vector<Executor*> Executors::all() {
  return {&sim, &control, &mapping, &mapping3d, &planning, &perception, &io, &dds};
}

void Executors::StartAll() {
  for (Executor* e : all()) e->Start();
}

void Executors::StopAll() {
  // The control loop's executor last but io: what drives the robot outlives what feeds it.
  for (Executor* e : {&sim, &perception, &planning, &mapping3d, &mapping, &control, &io}) e->Stop();
  for (Executor* e : all()) e->Stop();  // one added later and not ordered above still stops (Stop is idempotent)
}

std::size_t Executors::RunUntilIdle() {
  std::size_t total = 0;
  while (true) {
    std::size_t ran = 0;
    for (Executor* e : all()) ran += e->Poll();
    if (ran == 0) return total;
    total += ran;
  }
}

PeriodicTimer::PeriodicTimer(Executor& executor, std::chrono::nanoseconds period, std::function<void()> tick)
    : state_(std::make_shared<Executor::TimerState>(executor, period.count(), std::move(tick))) {
  DEMAND(period.count() > 0);
  if (executor.schedule() == Schedule::kLockstep) {
    executor.AddLockstepTimer(state_);
  } else {
    state_->timer.emplace(executor.context());
    boost::asio::post(executor.context(), [s = state_] { Executor::TimerState::Arm(s); });
  }
}

PeriodicTimer::~PeriodicTimer() { Stop(); }

void PeriodicTimer::Stop() {
  state_->stopped = true;
  if (state_->timer) boost::asio::post(state_->timer->get_executor(), [s = state_] { s->timer->cancel(); });
}

DeadlineTimer::DeadlineTimer(Executor& executor, std::function<void()> fire)
    : state_(std::make_shared<Executor::TimerState>(executor, 0, std::move(fire))) {
  state_->next_ns = Executor::TimerState::kUnarmed;
  if (executor.schedule() == Schedule::kLockstep) {
    executor.AddLockstepTimer(state_);
  } else {
    state_->timer.emplace(executor.context());
  }
}

DeadlineTimer::~DeadlineTimer() { Stop(); }

void DeadlineTimer::At(drivers::TimeNs when_ns) {
  if (state_->stopped) return;
  state_->next_ns = when_ns;
  if (state_->timer) Executor::TimerState::Arm(state_);  // a wait pending is cancelled by the new expiry
}

void DeadlineTimer::Stop() {
  state_->stopped = true;
  if (state_->timer) boost::asio::post(state_->timer->get_executor(), [s = state_] { s->timer->cancel(); });
}

}  // namespace corridor::server
