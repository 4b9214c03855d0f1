// Carries missions' lift requests (lifts/requests) to the building's lift controller (server/fleet/lifts.h) and
// publishes what it says of each lift in use (lifts/state): called to a floor (a call that goes unanswered is sent
// again at the next poll), polled every poll_s while in use, released and forgotten. Runs on the io executor, where
// the controller's HTTP exchanges complete.
#pragma once

#include <map>
#include <memory>
#include <string>

#include "server/fleet/lifts.h"
#include "server/runtime/node.h"

namespace corridor::server {

class LiftNode final : public PeriodicNode {
 public:
  LiftNode(Executor& io, Bus& bus, std::unique_ptr<LiftController> controller, double poll_s);
  ~LiftNode() override;
  void Activate() override;

 private:
  void Tick() override;
  void OnRequests(const LiftRequests& requests);
  void Call(const std::string& lift);
  void Report(const std::string& lift, nav::LiftReport report);
  void Publish();

  struct InUse {
    std::string floor;             // called to
    bool call_pending = false;     // the call is still to be (re)sent
    bool in_flight = false;        // a call or a state request is under way
    std::uint64_t generation = 0;  // answers to an earlier call are dropped
    nav::LiftReport report;
  };
  std::unique_ptr<LiftController> controller_;
  std::map<std::string, InUse> lifts_;
  std::uint64_t generation_ = 0;
  std::shared_ptr<bool> alive_ = std::make_shared<bool>(true);
};

}  // namespace corridor::server
