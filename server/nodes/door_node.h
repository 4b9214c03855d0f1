// Carries missions' door requests (doors/requests) to the building's door controller (server/fleet/doors.h) and
// publishes what it says of each door asked for (doors/state): asked to open, then polled every poll_s until open (a
// poll that goes unanswered is tried again; the mission's timeout bounds the wait); released, forgotten. Runs on the io
// executor, where the controller's HTTP exchanges complete.
#pragma once

#include <map>
#include <memory>
#include <string>

#include "server/fleet/doors.h"
#include "server/runtime/node.h"

namespace corridor::server {

class DoorNode final : public PeriodicNode {
 public:
  DoorNode(Executor& io, Bus& bus, std::unique_ptr<DoorController> controller, double poll_s);
  ~DoorNode() override;
  void Activate() override;

 private:
  void Tick() override;
  void OnRequests(const DoorRequests& requests);
  void Report(const std::string& door, nav::DoorReport report);
  void Publish();

  struct Asked {
    nav::DoorReport report{nav::DoorStatus::kOpening, ""};
    bool in_flight = false;
    std::uint64_t generation = 0;  // answers to an earlier asking are dropped
  };
  std::unique_ptr<DoorController> controller_;
  std::map<std::string, Asked> asked_;
  std::uint64_t generation_ = 0;
  std::shared_ptr<bool> alive_ = std::make_shared<bool>(true);
};

}  // namespace corridor::server
